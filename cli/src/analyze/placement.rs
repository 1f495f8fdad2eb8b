//! `ufcsr placement` (`ufcsr placement`): the command line of the
//! eHMI placement search (docs/placement.md), a page of options of its own
//! beside the other commands' (`args`), sharing their `--quiet`/`--json`/`-j`
//! words.

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;

use super::run::{Done, finish};
use crate::choices::EyeRule;
use crate::console::{Completion, Console};

/// Options of `ufcsr placement`.
#[derive(Args)]
pub(crate) struct PlacementArgs {
    /// Result folders of `ufcsr capture … --measure unobstructed --placement` (or archives, or their
    /// placement-frames.csv); several: scenarios or traffic conditions, scored by mean and worst case.
    #[arg(required = true)]
    results: Vec<PathBuf>,

    /// Sets of at most K physical displays are searched (a symmetric pair is two).
    #[arg(long, default_value_t = 3)]
    k: usize,

    /// Legible only when the characters' visible angular height reaches this, arcmin (default: ISO
    /// 9241-3's minimum character height, 16; MUTCD's road-sign 1 in per 40 ft is 7.16).
    #[arg(long, alias = "min-angular-height-arcmin", default_value_t = ufcsr::placement::Thresholds::default().min_character_height_arcmin)]
    min_character_height_arcmin: f64,

    /// The characters' height: a share of the display's height (0.5, the default: one line of
    /// capitals with margins) or metres (0.06m; parts, whose height is unknown, use 0.5).
    #[arg(long, value_name = "SHARE|METRESm", default_value = "0.5", value_parser = character_height)]
    character_height: ufcsr::placement::CharacterHeight,

    /// A display of known size is legible only when its width, foreshortened by the view angle,
    /// holds this many characters (0: no width check).
    #[arg(long, default_value_t = ufcsr::placement::Thresholds::default().min_characters)]
    min_characters: u32,

    /// Legible runs shorter than this many seconds do not count (FHWA: 1 s per word).
    #[arg(long, default_value_t = ufcsr::placement::Thresholds::default().min_dwell_s)]
    min_dwell_s: f64,

    /// Surfaces where no display is mounted, by the head noun of the part's name (comma-separated;
    /// default: wheels, tyres, rims and glass; '' allows every surface).
    #[arg(long, value_name = "NOUNS", value_delimiter = ',', default_values_t = ufcsr::placement::DEFAULT_NOT_MOUNTABLE.map(String::from))]
    not_mountable: Vec<String>,

    /// Patches of one part whose centres are within this many metres are one place (0: off).
    #[arg(long, default_value_t = ufcsr::placement::DEFAULT_REGION_RADIUS_M)]
    region_radius_m: f64,

    /// Bootstrap replicates over the archives behind P(best) (0: none).
    #[arg(long, default_value_t = ufcsr::placement::DEFAULT_REPLICATES)]
    replicates: usize,

    /// P(within EPSILON): how often a set is at most this many seconds below the best.
    #[arg(long, default_value_t = ufcsr::placement::DEFAULT_EPSILON_S)]
    epsilon_s: f64,

    /// Legible only when at least this share of the candidate's area is visible (0-1).
    #[arg(long, default_value_t = ufcsr::placement::Thresholds::default().min_visible_fraction)]
    min_visible_fraction: f64,

    /// Legible only when the mean angle between line of sight and surface normal is at most this, degrees.
    #[arg(long, default_value_t = ufcsr::placement::Thresholds::default().max_view_angle_deg)]
    max_view_angle_deg: f64,

    /// Seconds before the vehicle is nearest the pedestrian that count as the decision window.
    #[arg(long, default_value_t = ufcsr::placement::Thresholds::default().decision_window_s)]
    decision_window_s: f64,

    /// A frame is legible when either eye (`any`) or both (`both`) can read the candidate.
    #[arg(long, value_enum, default_value_t = EyeRule::Any)]
    eyes: EyeRule,

    /// The solid-angle rule instead of the three thresholds: legible when the visible solid angle
    /// reaches this many steradians; needed to score a rendered frames.csv (solid angles only) and
    /// to compare it with the exact measure (docs/placement.md §5).
    #[arg(long, value_name = "SR")]
    min_solid_angle_sr: Option<f64>,

    /// A left/right pair (front_fender_left + front_fender_right, mirrored patches) is chosen
    /// together: one choice, two displays.
    #[arg(long)]
    symmetric: bool,

    /// The vehicle model the chosen placements are drawn on (placement.png); default: the first
    /// archive's vehicle.glb (written by ufcsr capture).
    #[arg(long, value_name = "GLB")]
    mesh: Option<PathBuf>,

    /// Output folder for placement.json, placement.csv, placement-combinations.csv and published-locations.csv.
    #[arg(long, short, value_name = "DIR")]
    out: PathBuf,

    /// Candidates shown on the console.
    #[arg(long, default_value_t = 15)]
    top: usize,
}

/// Runs the search and writes its files.
pub(crate) fn run_placement(args: PlacementArgs, console: &Console) -> Result<Completion> {
    let options = ufcsr::PlacementOptions {
        thresholds: ufcsr::placement::Thresholds {
            min_character_height_arcmin: args.min_character_height_arcmin,
            character_height: args.character_height,
            min_characters: args.min_characters,
            min_dwell_s: args.min_dwell_s,
            min_visible_fraction: args.min_visible_fraction,
            max_view_angle_deg: args.max_view_angle_deg,
            decision_window_s: args.decision_window_s,
            eyes: args.eyes.into(),
            min_solid_angle_sr: args.min_solid_angle_sr,
        },
        k: args.k,
        symmetric: args.symmetric,
        not_mountable: args.not_mountable.into_iter().filter(|n| !n.trim().is_empty()).collect(),
        region_radius_m: args.region_radius_m,
        resampling: ufcsr::placement::Resampling {
            replicates: args.replicates,
            epsilon_s: args.epsilon_s,
            ..ufcsr::placement::Resampling::default()
        },
        mesh: args.mesh,
        ..ufcsr::PlacementOptions::new(args.results)
    };
    answer(&options, &args.out, args.top, console)
}

/// The search of `options`, its files written to `out` and the answer
/// printed (the `top` candidates, the best sets with their intervals, the
/// places published studies tested): `placement`'s and `where`'s one way.
pub(crate) fn answer(
    options: &ufcsr::PlacementOptions,
    out: &Path,
    top: usize,
    console: &Console,
) -> Result<Completion> {
    let placement = ufcsr::placement(options)?;
    let written = ufcsr::write_placement(&placement, out)?;
    let picture = match &written.picture {
        Some(picture) => format!(
            "\nthe chosen placements on the vehicle: {} (and {} for a paper, 183 mm)",
            picture.overview.display(),
            picture.pdf.display()
        ),
        None => "\nno vehicle model (no vehicle.glb in the archive): give --mesh for placement.png".into(),
    };
    let published = ufcsr::placement::published_locations(&placement);
    let published_csv = ufcsr::placement::write_published_locations(&published, out, &placement.inputs)?;
    let text = format!(
        "{}\n{}\nwrote {}, {}, {} and {}{picture}",
        ufcsr::format_placement(&placement, top).trim_end(),
        ufcsr::placement::format_published_locations(&published, placement.document.archives.len())
            .trim_end(),
        written.json.display(),
        written.csv.display(),
        written.combinations_csv.display(),
        published_csv.display()
    );
    let mut files =
        vec![written.json.clone(), written.csv.clone(), written.combinations_csv.clone(), published_csv];
    files.extend(
        written
            .picture
            .iter()
            .flat_map(|p| [p.overview.clone(), p.pdf.clone()].into_iter().chain(p.views.clone())),
    );
    Ok(finish(
        console,
        Done { completion: Completion::Done, written: files, text, facts: serde_json::json!({}) },
    ))
}

fn character_height(text: &str) -> std::result::Result<ufcsr::placement::CharacterHeight, String> {
    ufcsr::placement::parse_character_height(text).map_err(|e| e.to_string())
}
