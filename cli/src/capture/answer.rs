//! `ufcsr where`: one command for "where should the eHMI go" (issue 45 §3).
//! It is the documented two-step route run as one: the exact capture with
//! display-sized candidates (`ufcsr capture … --measure unobstructed
//! --placement --display WxH`, through the capture's own option parser,
//! [`CaptureArgs::from_words`]) of every scenario, then the placement over
//! them (`ufcsr placement`'s [`answer`]), and it prints the answer with the
//! rules it used (display size, surfaces left out, observer, legibility)
//! and the two commands it ran, so a user can take either route and get
//! the same files. Every option is checked before anything is measured. A
//! scene that measures several vehicles gets one answer per vehicle, each
//! from that vehicle's own exact archives (the others occluding it).

use std::ffi::OsString;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use super::captures::{CaptureArgs, apply_rig, scenario_names};
use super::source::SourceArgs;
use crate::analyze::placement::answer;
use crate::choices::{Backend, BodyType, DemoTraffic};
use crate::console::{Completion, Console, say, shown};

/// The display size asked about when none is given (the README's and placement.md's).
const DEFAULT_DISPLAY: &str = "0.40x0.15";
/// The share of texels measured when none is given: the placement brackets each
/// candidate's legible seconds by this sample (docs/placement.md).
const DEFAULT_SAMPLE: &str = "1/16";
/// Candidates listed before the best sets.
const TOP: usize = 10;

/// Options of `ufcsr where`.
#[derive(Args)]
pub(crate) struct WhereArgs {
    #[command(flatten)]
    scene: SourceArgs,
    /// With demo: a body of the parametric family, with its typical dimensions, in place of the
    /// truck (docs/vehicles.md).
    #[arg(long, value_enum, conflicts_with = "traffic")]
    body: Option<BodyType>,
    /// With demo: a second pickup in traffic, alongside the truck (adjacent-lane) or ahead of it
    /// (lead-car).
    #[arg(long, value_enum)]
    traffic: Option<DemoTraffic>,
    /// One scenario, or `all` (the default: the answer's interval is over the scenarios).
    #[arg(long, default_value = "all")]
    scenario: String,
    /// The display asked about, width x height in metres; candidate patches of this size are
    /// laid every 10 cm over the outward-facing surface.
    #[arg(long, value_name = "WxH", default_value = DEFAULT_DISPLAY)]
    display: String,
    /// Sets of at most K physical displays are searched (default 3; a symmetric pair is two).
    #[arg(long)]
    k: Option<usize>,
    /// A left/right pair is chosen together: one choice, two displays.
    #[arg(long)]
    symmetric: bool,
    /// The share of texels measured, e.g. 1/16 (the default) or 1 for every texel; each
    /// candidate's legible seconds carry the bracket this sample puts on them.
    #[arg(long, default_value = DEFAULT_SAMPLE)]
    sample: String,
    /// Canonical palette size, W or WxH (default 4096, as `capture`'s).
    #[arg(long, value_name = "W|WxH")]
    palette_size: Option<String>,
    /// Frames measured: `all` (the default), every Nth (`all/N`, the middle of each N frames) or a list
    /// like 0,30,60-90/10.
    #[arg(long)]
    frames: Option<String>,
    /// The observer: `median` (the default: a median US adult's eyes, unless the scene sets its
    /// own), `paper` (the seed paper's camera pair) or rig overrides as JSON.
    #[arg(long, value_name = "median|paper|JSON")]
    rig: Option<String>,
    /// Surfaces where no display is mounted, by the head noun of the part's name
    /// (comma-separated; default: wheels, tyres, rims and glass; '' allows every surface).
    #[arg(long, value_name = "NOUNS", value_delimiter = ',')]
    not_mountable: Option<Vec<String>>,
    /// Output folder: runs/SCENARIO (each scenario's measured archive) and answer/ (placement.json,
    /// placement.csv, placement.png, …).
    #[arg(long, default_value = "where")]
    out: PathBuf,
    /// GPU backend (the capture writes the archive's palette and PIdT with it).
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    backend: Backend,
}

/// What `where` runs, checked: the capture's options, the placement's, and
/// the folders each scenario's archive goes to.
struct Plan {
    source: super::Source,
    /// The words after the source, as `ufcsr capture SOURCE …` takes them.
    capture_words: Vec<OsString>,
    capture: CaptureArgs,
    /// One answer, or one per measured vehicle of a several-vehicle scene.
    answers: Vec<Answer>,
    observer: String,
}

/// One placement answer: for the scene's vehicle, or for one vehicle of a
/// scene that measures several.
struct Answer {
    /// The vehicle's name where the scene measures several.
    vehicle: Option<String>,
    placement: ufcsr::PlacementOptions,
    answer: PathBuf,
}

/// The plan of `args`: every option parsed and checked before anything runs.
fn plan(args: &WhereArgs) -> anyhow::Result<(Plan, Vec<String>)> {
    let source = args.scene.source_with(args.traffic, args.body)?;
    let scene = source.scene()?;
    let names = scenario_names(&scene, Some(&args.scenario))?;
    let runs = args.out.join("runs");
    let all = args.scenario.eq_ignore_ascii_case("all");
    let vehicles: Vec<String> = scene.fleet.iter().map(|vehicle| vehicle.name.clone()).collect();
    // Each scenario in runs/NAME: `--scenario all` makes the sub-folders itself; several
    // vehicles each in runs/VEHICLE (runs/VEHICLE/NAME with `all`), made by the capture.
    let capture_out = if all || !vehicles.is_empty() { runs.clone() } else { runs.join(&names[0]) };
    let mut words: Vec<OsString> =
        ["--measure", "unobstructed", "--placement", "--display"].map(OsString::from).to_vec();
    words.push(args.display.clone().into());
    words.extend(["--sample".into(), args.sample.clone().into(), "--scenario".into()]);
    words.push(if all { "all".into() } else { names[0].clone().into() });
    for (flag, value) in
        [("--palette-size", &args.palette_size), ("--frames", &args.frames), ("--rig", &args.rig)]
    {
        if let Some(value) = value {
            words.extend([OsString::from(flag), value.into()]);
        }
    }
    words.extend([OsString::from("--out"), capture_out.into_os_string()]);
    let capture = CaptureArgs::from_words(&[words.clone(), backend_words(args.backend)].concat())?;
    let answers = if vehicles.is_empty() {
        let inputs = names.iter().map(|name| runs.join(name)).collect();
        vec![Answer {
            vehicle: None,
            placement: placement_options(args, inputs)?,
            answer: args.out.join("answer"),
        }]
    } else {
        let mut answers = Vec::new();
        for vehicle in vehicles {
            let archives = runs.join(&vehicle);
            let inputs =
                if all { names.iter().map(|name| archives.join(name)).collect() } else { vec![archives] };
            let placement = placement_options(args, inputs)?;
            answers.push(Answer {
                placement,
                answer: args.out.join("answer").join(&vehicle),
                vehicle: Some(vehicle),
            });
        }
        answers
    };
    ufcsr_capture::parse_display(&args.display)?;
    super::captures::parse_fraction(&args.sample)?;
    let mut described = scene;
    apply_rig(&mut described, &capture)?;
    let observer = ufcsr_capture::study::describe_observer(&described.rig);
    Ok((Plan { source, capture_words: words, capture, answers, observer }, names))
}

/// The placement's options of `args` over the archives `inputs`, checked.
fn placement_options(args: &WhereArgs, inputs: Vec<PathBuf>) -> anyhow::Result<ufcsr::PlacementOptions> {
    let mut placement = ufcsr::PlacementOptions::new(inputs);
    placement.k = args.k.unwrap_or(placement.k);
    placement.symmetric = args.symmetric;
    if let Some(nouns) = &args.not_mountable {
        placement.not_mountable = nouns.iter().filter(|n| !n.trim().is_empty()).cloned().collect();
    }
    placement.check()?;
    Ok(placement)
}

/// `--backend`, where it is not the default (a hidden switch of the capture).
fn backend_words(backend: Backend) -> Vec<OsString> {
    match clap::ValueEnum::to_possible_value(&backend) {
        Some(value) if backend != Backend::Auto => vec!["--backend".into(), value.get_name().into()],
        _ => Vec::new(),
    }
}

/// Measures, ranks and prints the answer.
pub(crate) fn run_where(args: WhereArgs, console: &Console) -> anyhow::Result<Completion> {
    let (plan, names) = plan(&args)?;
    say!(
        console,
        "where should a {} m display go on {}? {} {}, exact measure of {} of the texels, frames {}",
        args.display,
        plan.source.describe(),
        if names.len() == 1 { "scenario" } else { "scenarios" },
        names.join(", "),
        args.sample,
        args.frames.as_deref().unwrap_or("all")
    );
    say!(console, "{}", rules(&plan));
    console.fact("observer", &plan.observer);
    let start = Instant::now();
    super::capture_source(&plan.source, &plan.capture, 0, &console.muted())?;
    let runs: Vec<String> =
        plan.answers.iter().flat_map(|one| &one.placement.inputs).map(|run| shown(run)).collect();
    say!(
        console,
        "measured {} scenario(s) in {:.1} s: {}\n",
        names.len(),
        start.elapsed().as_secs_f64(),
        runs.join(", ")
    );
    let mut completion = Completion::Done;
    for one in &plan.answers {
        if let Some(vehicle) = &one.vehicle {
            say!(console, "== vehicle {vehicle} (the scene's other vehicles occluding it)");
        }
        if answer(&one.placement, &one.answer, TOP, console)? == Completion::WithFailures {
            completion = Completion::WithFailures;
        }
        match &one.vehicle {
            Some(vehicle) => console.fact_item(
                "answers",
                serde_json::json!({ "vehicle": vehicle, "answer": shown(&one.answer.join("placement.json")) }),
            ),
            None => console.fact("answer", shown(&one.answer.join("placement.json"))),
        }
    }
    say!(
        console,
        "\nthe same {} in two steps (to change a threshold, rerun the second):\n{}",
        if plan.answers.len() == 1 { "answer" } else { "answers" },
        two_steps(&plan)
    );
    console.fact("runs", runs);
    Ok(completion)
}

/// The rules the answer used, one line each.
fn rules(plan: &Plan) -> String {
    let first = &plan.answers[0].placement;
    let t = &first.thresholds;
    let height = match t.character_height {
        ufcsr::placement::CharacterHeight::Fraction(share) => format!("{share} of the display's height"),
        ufcsr::placement::CharacterHeight::Metres(metres) => format!("{metres} m"),
    };
    let nouns = &first.not_mountable;
    let left_out = if nouns.is_empty() { "none".to_string() } else { nouns.join(", ") };
    format!(
        "  observer: {}\n  not mountable (scored, never chosen): {left_out}; a part holds a display only where a \
         display patch fits on it\n  legible: characters of {height} seen at {} arcmin or more, {} characters \
         across the foreshortened width, {:.0} % of it visible, at most {}° off the line of sight, for runs of \
         {} s or more (docs/placement.md)",
        plan.observer,
        t.min_character_height_arcmin,
        t.min_characters,
        100.0 * t.min_visible_fraction,
        t.max_view_angle_deg,
        t.min_dwell_s
    )
}

/// The two commands `where` ran, as a user would type them.
fn two_steps(plan: &Plan) -> String {
    let quoted = |word: &str| {
        if word.chars().all(|c| c.is_ascii_alphanumeric() || "-_./=:,".contains(c)) {
            word.to_string()
        } else {
            format!("'{}'", word.replace('\'', r"'\''"))
        }
    };
    let words =
        |list: &[OsString]| -> Vec<String> { list.iter().map(|w| quoted(&w.to_string_lossy())).collect() };
    let source = match &plan.source {
        super::Source::Scene(file) => format!("scene {}", quoted(&file.to_string_lossy())),
        super::Source::Unity(file) => format!("unity {}", quoted(&file.to_string_lossy())),
        demo => demo.describe(),
    };
    let placements = plan.answers.iter().map(|one| {
        let p = &one.placement;
        let mut placement: Vec<String> = p.inputs.iter().map(|run| quoted(&run.to_string_lossy())).collect();
        placement.extend(["--k".to_string(), p.k.to_string()]);
        if p.symmetric {
            placement.push("--symmetric".into());
        }
        if p.not_mountable != ufcsr::PlacementOptions::new(Vec::new()).not_mountable {
            placement.push(format!("--not-mountable={}", quoted(&p.not_mountable.join(","))));
        }
        placement.extend(["--out".to_string(), quoted(&one.answer.to_string_lossy())]);
        format!("\n  ufcsr placement {}", placement.join(" "))
    });
    format!(
        "  ufcsr capture {source} {}{}",
        words(&plan.capture_words).join(" "),
        placements.collect::<String>()
    )
}
