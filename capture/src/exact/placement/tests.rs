//! Known answers of the placement measure: a facing plate's angular height
//! is 2·atan(h / 2d), so it reaches the legibility threshold exactly at the
//! distance the threshold implies; a display patch behind a box is not
//! visible in the eye-frames the box covers it and legible in those it does
//! not, and one behind a box driving past is hidden in exactly the frames
//! the box covers it; patches fit inside the surface, hold W × H of it and pair with their
//! mirror images; every place published eHMI studies tested is a named
//! candidate on the truck and every family body.

use glam::{DMat4, DVec3, Vec3, dvec3};

use super::frames::{Seen, measure_eye_frame};
use super::labels::LabelSet;
use super::patches::{PlacedPatch, place_patches};
use super::{ExactInputs, parse_display};
use crate::exact::geometry::{Obstacles, eye_frame};
use crate::exact::points::surface_samples;
use crate::exact::types::{EyeFrame, PlacementCandidates, SurfaceSamples};
use crate::scene::{Mesh, Occluders, Scene, ValueOrTrack, look_to, reversed_z_perspective};
use crate::texture::{background_texel, unwrap_islands_avoiding};

/// A plate `w` wide (along y) and `h` high in the plane x = 0, centred on (0, 0, `z`).
fn plate(w: f32, h: f32, z: f32) -> Mesh {
    let mut mesh = Mesh::default();
    let corner = |y: f32, dz: f32| Vec3::new(0.0, y, z + dz);
    mesh.add_quad(
        "plate",
        corner(-w / 2.0, -h / 2.0),
        corner(w / 2.0, -h / 2.0),
        corner(w / 2.0, h / 2.0),
        corner(-w / 2.0, h / 2.0),
    );
    mesh
}

fn scene_with(vehicle: Mesh, occluders: Occluders) -> Scene {
    let mut scene = Scene::demo();
    scene.vehicle = vehicle;
    scene.occluders = occluders;
    scene.rig.pedestrian = ValueOrTrack::Fixed([0.0, 0.0, 0.0]);
    scene
}

fn samples_of(mesh: &Mesh, palette: [u32; 2]) -> SurfaceSamples {
    let unwrapped = unwrap_islands_avoiding(mesh, palette, background_texel(palette)).unwrap();
    surface_samples(mesh, &unwrapped, 1.0, 1, 1)
}

/// An eye at `eye` looking at `target`.
fn eye_at(obstacles: &Obstacles, eye: DVec3, target: DVec3) -> EyeFrame {
    let view_proj = reversed_z_perspective(60f64.to_radians(), 1.0, 0.3, 1000.0)
        * look_to(eye, (target - eye).normalize(), DVec3::Z);
    eye_frame(obstacles, &DMat4::IDENTITY, &[], eye, &view_proj)
}

fn inputs<'a>(scene: &'a Scene, samples: &'a SurfaceSamples, obstacles: &'a Obstacles) -> ExactInputs<'a> {
    ExactInputs {
        scene,
        samples,
        eye_frames: &[],
        frame_records: &[],
        obstacles,
        sample_fraction: 1.0,
        frame_s: 0.1,
    }
}

/// The parts and 0.40 m × 0.15 m display patches every 10 cm as labels.
fn display_patches(inputs: &ExactInputs) -> (LabelSet, Vec<super::patches::PlacedPatch>) {
    let mut labels = LabelSet::parts(&inputs.scene.vehicle.parts, inputs.samples);
    let patches = place_patches(inputs, [0.40, 0.15], 0.10);
    labels.add_patches(&patches, inputs.samples);
    (labels, patches)
}

/// The label of the first patch centred near y = 0 at a height `at_z` accepts.
fn centred_patch(patches: &[super::patches::PlacedPatch], at_z: impl Fn(f64) -> bool) -> usize {
    1 + patches.iter().position(|p| at_z(p.centre.z) && p.centre.y.abs() < 0.1).expect("a centred patch")
}

#[test]
fn a_facing_plate_reaches_sixteen_arcmin_exactly_at_the_distance_it_implies() {
    let (w, h, z) = (0.40, 0.15, 1.6);
    let scene = scene_with(plate(w as f32, h as f32, z as f32), Occluders::default());
    let samples = samples_of(&scene.vehicle, [512, 512]);
    let obstacles = Obstacles::new(&scene);
    let labels = LabelSet::parts(&scene.vehicle.parts, &samples);
    let inputs = inputs(&scene, &samples, &obstacles);
    let seen_from = |d: f64| -> Seen {
        let frame = eye_at(&obstacles, dvec3(d, 0.0, z), dvec3(0.0, 0.0, z));
        measure_eye_frame(&inputs, &labels, &frame)[0].expect("the plate is visible")
    };
    // Sample points stand for texels: the extent is exact to about one texel.
    let texel_m =
        (samples.samples.iter().map(|s| s.area_m2).sum::<f64>() / samples.samples.len() as f64).sqrt();
    assert!(texel_m < 1e-3, "{texel_m}");
    for d in [2.0, 10.0, 40.0] {
        let seen = seen_from(d);
        let exact = (2.0 * (h / (2.0 * d)).atan()).to_degrees();
        let tolerance = (texel_m / d).to_degrees();
        assert!((seen.angular_height_deg - exact).abs() <= tolerance, "{d} m: {seen:?} vs {exact}");
        assert!((seen.visible_fraction - 1.0).abs() < 1e-9);
        assert!(seen.view_angle_deg < (w / 2.0 / d).atan().to_degrees() + 1e-9);
    }
    // 16 arcmin: d* = h / (2 tan 8') = 32.228 m; one texel of height moves it
    // by d* · texel / h. Legible just inside that band, not just outside.
    let implied = h / (2.0 * (8.0f64 / 60.0).to_radians().tan());
    assert!((implied - 32.228).abs() < 1e-3, "{implied}");
    let band = implied * texel_m / h;
    assert!(seen_from(implied - band).angular_height_deg * 60.0 >= 16.0);
    assert!(seen_from(implied + band).angular_height_deg * 60.0 < 16.0);
}

/// Issue 42 §4: a display patch's angular height comes from its exact outline, so the frame at
/// which its characters reach 16′ while the eye walks towards it is the closed form's, at any
/// palette (the samples' extent read up to a texel tall: 2 frames early at 256² here, on time at 512²).
#[test]
fn a_patchs_legibility_onset_approaching_a_fixed_plate_is_the_closed_forms_within_one_frame() {
    let h = 0.15;
    // Characters half the display's height reach 16 arcmin: 2·atan(h / 2d) · 60 · 0.5 ≥ 16.
    let legible = |height_deg: f64| height_deg * 60.0 * 0.5 >= 16.0;
    // The eye walks from 19 m to 13 m at 0.1 m per frame (onset near 16.1 m).
    let distance = |frame: usize| 19.0 - 0.1 * frame as f64;
    let frames = 61;
    let closed =
        (0..frames).find(|&f| legible((2.0 * (h / (2.0 * distance(f))).atan()).to_degrees())).unwrap();
    for palette in [[256, 256], [512, 512]] {
        let scene = scene_with(plate(1.0, 1.0, 2.0), Occluders::default());
        let samples = samples_of(&scene.vehicle, palette);
        let obstacles = Obstacles::new(&scene);
        let inputs = inputs(&scene, &samples, &obstacles);
        let (labels, patches) = display_patches(&inputs);
        let label = centred_patch(&patches, |z| (z - 2.0).abs() < 0.06);
        let centre = patches[label - 1].centre;
        // The same patch measured from its samples' extent (the old way), for the comparison.
        let mut sampled = labels.clone();
        sampled.outlines.iter_mut().for_each(|o| *o = None);
        let height_with = |labels: &LabelSet, frame: usize| {
            let eye = dvec3(distance(frame), centre.y, centre.z);
            let seen = measure_eye_frame(&inputs, labels, &eye_at(&obstacles, eye, centre));
            seen[label].expect("the patch is visible").angular_height_deg
        };
        let height = |frame: usize| height_with(&labels, frame);
        let onset = (0..frames).find(|&f| legible(height(f))).expect("legible by 13 m");
        let old = (0..frames).find(|&f| legible(height_with(&sampled, f))).expect("legible by 13 m");
        eprintln!("{palette:?}: onset frame {onset} (outline), {old} (samples), closed form {closed}");
        assert!(onset.abs_diff(closed) <= 1, "{palette:?}: onset frame {onset}, closed form {closed}");
        assert!(old <= closed, "the samples' extent never reads late: {old} against {closed}");
        // The outline is exact: the height at the closed form's frame is 2·atan(h / 2d).
        let exact = (2.0 * (h / (2.0 * distance(closed))).atan()).to_degrees();
        assert!((height(closed) - exact).abs() < 1e-9 * exact, "{palette:?}");
    }
}

#[test]
fn a_patch_behind_a_box_is_hidden_exactly_while_the_box_covers_it() {
    // A 1 m plate at x = 0 (z 1.5 to 2.5), a box in front of its lower half
    // (x 0.5 to 0.7, z up to 1.95). From straight ahead at eye height 2.2 the
    // box hides the lower patches; from 1 m higher up it hides none of them.
    let mut occluders = Occluders::default();
    occluders.add_box(dvec3(0.5, -1.0, 0.0), dvec3(0.7, 1.0, 1.95));
    let scene = scene_with(plate(1.0, 1.0, 2.0), occluders);
    let samples = samples_of(&scene.vehicle, [512, 512]);
    let obstacles = Obstacles::new(&scene);
    let inputs = inputs(&scene, &samples, &obstacles);
    let (labels, patches) = display_patches(&inputs);
    let low = centred_patch(&patches, |z| z < 1.7);
    let high = centred_patch(&patches, |z| z > 2.3);
    let behind =
        measure_eye_frame(&inputs, &labels, &eye_at(&obstacles, dvec3(3.0, 0.0, 2.2), dvec3(0.0, 0.0, 2.0)));
    assert_eq!(behind[low], None, "the box covers the low patch");
    assert!(behind[high].is_some_and(|s| s.visible_fraction == 1.0));
    let above =
        measure_eye_frame(&inputs, &labels, &eye_at(&obstacles, dvec3(3.0, 0.0, 12.0), dvec3(0.0, 0.0, 2.0)));
    assert!(above[low].is_some_and(|s| s.visible_fraction == 1.0), "{:?}", above[low]);
}

/// A box 0.2 m thick, 2 m wide and 1.95 m tall driving across in front of
/// the plate of the test above (x = 0.6, y from −2.5 to +2.5 in 1 s), seen
/// from 3 m ahead at eye height 2.2 m at 10 fps (centre y = −2.5 + 0.5 ·
/// frame). The low patch's rays reach |y| ≤ 0.26 m in the box, so the box
/// (|y − c| ≤ 1) hides the patch wholly for |c| ≤ 0.74 (frames 4–6), partly
/// for |c| = 1 (frames 3 and 7) and not at all for |c| ≥ 1.26.
fn crossing_box() -> crate::scene::MovingOccluder {
    use crate::scene::track::{Key, Track};
    let mut mesh = Mesh::default();
    mesh.add_box(Vec3::new(-0.1, -1.0, 0.0), Vec3::new(0.1, 1.0, 1.95), [Some("box"); 6]);
    let keys = vec![Key::linear(0.0, [0.6, -2.5, 0.0]), Key::linear(1.0, [0.6, 2.5, 0.0])];
    crate::scene::MovingOccluder {
        name: "crossing box".into(),
        mesh,
        path: crate::scene::OccluderPath::Tracks {
            position: ValueOrTrack::Keys(Track { keys }),
            yaw_deg: ValueOrTrack::Fixed([0.0]),
        },
    }
}

#[test]
fn a_patch_behind_a_moving_box_is_hidden_in_exactly_the_frames_the_box_covers_it() {
    use crate::scene::track::{Key, Motion, Track};
    let occluders = Occluders { moving: vec![crossing_box()], ..Occluders::default() };
    let mut scene = scene_with(plate(1.0, 1.0, 2.0), occluders);
    scene.rig.pedestrian = ValueOrTrack::Fixed([3.0, 0.0, 0.0]);
    scene.rig.eye_height_m = 2.2;
    scene.rig.look_at_vehicle = [0.0, 0.0, 2.0];
    scene.rig.fps = 10.0;
    let still = Motion {
        position: Track { keys: vec![Key::linear(0.0, [0.0; 3])] },
        yaw_deg: Track { keys: vec![Key::linear(0.0, [0.0])] },
    };
    let scenario = crate::scene::Scenario { name: "S".into(), duration_s: 1.0, motion: still };
    let samples = samples_of(&scene.vehicle, [512, 512]);
    let obstacles = Obstacles::new(&scene);
    let frames: Vec<u32> = (0..=10).collect();
    let (eye_frames, _) = crate::exact::geometry::eye_frames(&scene, &scenario, &frames, &obstacles).unwrap();
    let inputs = inputs(&scene, &samples, &obstacles);
    let (labels, patches) = display_patches(&inputs);
    let low = centred_patch(&patches, |z| z < 1.7);
    for (index, eye_frame) in eye_frames.iter().enumerate() {
        let frame = index / 2;
        let seen = measure_eye_frame(&inputs, &labels, eye_frame)[low];
        match frame {
            4..=6 => assert_eq!(seen, None, "frame {frame}: the box covers the low patch"),
            3 | 7 => assert!(
                seen.is_some_and(|s| s.visible_fraction > 0.05 && s.visible_fraction < 0.95),
                "frame {frame}: {seen:?}"
            ),
            _ => assert!(seen.is_some_and(|s| s.visible_fraction > 1.0 - 1e-9), "frame {frame}: {seen:?}"),
        }
    }
}

#[test]
fn patches_fit_inside_the_surface_hold_their_area_and_pair_with_their_mirrors() {
    let scene = scene_with(plate(1.0, 1.0, 2.0), Occluders::default());
    let samples = samples_of(&scene.vehicle, [512, 512]);
    let obstacles = Obstacles::new(&scene);
    let inputs = inputs(&scene, &samples, &obstacles);
    let [w, h] = parse_display("0.40x0.15").unwrap();
    let patches = place_patches(&inputs, [w, h], 0.10);
    let texel_m =
        (samples.samples.iter().map(|s| s.area_m2).sum::<f64>() / samples.samples.len() as f64).sqrt();
    assert!(patches.len() >= 20, "{} patches", patches.len());
    for patch in &patches {
        assert!(patch.centre.y.abs() <= 0.5 - w / 2.0 + 0.01, "{} overhangs", patch.name);
        assert!((patch.centre.z - 2.0).abs() <= 0.5 - h / 2.0 + 0.01, "{} overhangs", patch.name);
        assert!(patch.normal.x.abs() > 0.999 && patch.up.z > 0.999, "{patch:?}");
        // Samples whose centre lies inside: W × H to about half a texel along the rim.
        let area: f64 = patch.members.iter().map(|&s| samples.samples[s as usize].area_m2).sum();
        assert!((area - w * h).abs() <= (w + h) * texel_m, "{}: {area} m²", patch.name);
        if patch.centre.y.abs() > 0.06 {
            let mirror = patch.mirror.as_ref().expect("an off-centre patch has a mirror");
            let other = patches.iter().find(|p| &p.name == mirror).unwrap();
            assert!(
                (other.centre.y + patch.centre.y).abs() <= 0.05
                    && (other.centre.z - patch.centre.z).abs() <= 0.05
            );
        }
    }
    // Mirrors name each other (issue 34: `placement` refuses one-sided ones).
    for patch in &patches {
        if let Some(mirror) = &patch.mirror {
            let other = patches.iter().find(|p| &p.name == mirror).unwrap();
            assert_eq!(other.mirror.as_deref(), Some(patch.name.as_str()), "{} ↔ {mirror}", patch.name);
        }
    }
    assert!(parse_display("0.4").is_err() && parse_display("0x1").is_err() && parse_display("ax1").is_err());
    assert_eq!(PlacementCandidates::default().spacing_m, 0.10);
}

#[test]
fn patch_names_are_unique_where_the_surface_crosses_a_cube_face() {
    // A plate tilted by about 1° crossing the cube face x = 0.10 at z = 1.95: the cubes
    // on either side of the face both hold surface, and their centres, a few millimetres
    // apart, round to one name; the first stands for both.
    let mut mesh = Mesh::default();
    let corner = |y: f32, dz: f32| Vec3::new(0.1 + 0.02 * (dz + 0.05), y, 2.0 + dz);
    mesh.add_quad("plate", corner(-0.5, -0.5), corner(0.5, -0.5), corner(0.5, 0.5), corner(-0.5, 0.5));
    let scene = scene_with(mesh, Occluders::default());
    let samples = samples_of(&scene.vehicle, [512, 512]);
    let obstacles = Obstacles::new(&scene);
    let patches = place_patches(&inputs(&scene, &samples, &obstacles), [0.40, 0.15], 0.10);
    let mut names: Vec<&str> = patches.iter().map(|p| p.name.as_str()).collect();
    assert!(names.iter().any(|name| name.contains("z1.95")), "{names:?}");
    // The display's size is in every name, so runs with other sizes are other candidates.
    assert!(names.iter().all(|name| name.starts_with("plate@0.40x0.15@x")), "{names:?}");
    names.sort_unstable();
    let count = names.len();
    names.dedup();
    assert_eq!(names.len(), count, "a name given twice");
}

#[test]
fn a_flat_plate_holds_the_patches_that_fit_on_it_exactly() {
    // A 1 m × 1 m plate in x = 0 (y −0.5 to 0.5, z 1.5 to 2.5), cubes of 0.10 m:
    // centres at the cube middles, y and z = ±0.05, ±0.15, … ±0.45. A 0.40 × 0.15
    // display fits (≥ 90 % covered) where it overhangs by at most 0.04 m across
    // and 0.015 m in height: |y| ≤ 0.25 (6 columns), |z − 2| ≤ 0.35 (8 rows).
    let scene = scene_with(plate(1.0, 1.0, 2.0), Occluders::default());
    let samples = samples_of(&scene.vehicle, [256, 256]);
    let obstacles = Obstacles::new(&scene);
    let patches = place_patches(&inputs(&scene, &samples, &obstacles), [0.40, 0.15], 0.10);
    assert_eq!(patches.len(), 48, "{:?}", patches.iter().map(|p| &p.name).collect::<Vec<_>>());
    for patch in &patches {
        let [y, z] = [patch.centre.y, patch.centre.z - 2.0];
        let on_grid = |v: f64| ((v / 0.1 - 0.5).round() - (v / 0.1 - 0.5)).abs() < 1e-6;
        assert!(patch.centre.x == 0.0 && on_grid(y) && on_grid(z), "{}", patch.name);
        assert!(y.abs() < 0.26 && z.abs() < 0.36, "{}", patch.name);
        let mirror = patch.mirror.as_deref().expect("every patch has its mirror image");
        assert!(mirror.contains(&format!("y{:.2}z", -y)), "{} ↔ {mirror}", patch.name);
    }
}

/// A 1 m × 1 m plate in x = 0 (y −0.5 to 0.5, z 1.5 to 2.5) whose side
/// y < `cut` is the part `right` and side y > `cut` the part `left`.
fn split_plate(right: &str, left: &str, cut: f32) -> Mesh {
    let mut mesh = Mesh::default();
    let corner = |y: f32, z: f32| Vec3::new(0.0, y, z);
    mesh.add_quad(right, corner(-0.5, 1.5), corner(cut, 1.5), corner(cut, 2.5), corner(-0.5, 2.5));
    mesh.add_quad(left, corner(cut, 1.5), corner(0.5, 1.5), corner(0.5, 2.5), corner(cut, 2.5));
    mesh
}

/// The patches of 0.40 × 0.15 m displays on `mesh` (samples 256²), with
/// the parts each one's samples lie on, sorted.
fn patches_and_parts_held(mesh: Mesh) -> (Vec<PlacedPatch>, Vec<(String, Vec<String>)>) {
    let scene = scene_with(mesh, Occluders::default());
    let samples = samples_of(&scene.vehicle, [256, 256]);
    let obstacles = Obstacles::new(&scene);
    let patches = place_patches(&inputs(&scene, &samples, &obstacles), [0.40, 0.15], 0.10);
    let parts_held: Vec<(String, Vec<String>)> = patches
        .iter()
        .map(|patch| {
            let mut parts: Vec<String> = patch
                .members
                .iter()
                .map(|&m| {
                    let triangle = samples.samples[m as usize].triangle as usize;
                    scene.vehicle.parts[scene.vehicle.triangle_part[triangle] as usize].clone()
                })
                .collect();
            parts.sort();
            parts.dedup();
            (patch.name.clone(), parts)
        })
        .collect();
    (patches, parts_held)
}

#[test]
fn a_display_patch_never_reaches_from_a_body_panel_onto_glass_but_spans_two_panels() {
    // The plate of `a_flat_plate_holds_the_patches_that_fit_on_it_exactly`
    // (48 patches: |y| ≤ 0.25 in 6 columns, 8 rows), cut at y = 0. Two body
    // panels: a display may span the seam, so the same 48. A panel beside a
    // window: a patch holds only surface of its centre's kind, and a 0.40 m
    // display needs 0.36 m of it across (90 %): centred at y = ∓0.05 it has
    // 0.25 m, at ∓0.15 0.35 m, at ∓0.25 the whole 0.40, so only the outer
    // columns stay, 8 patches on the panel and 8 on the window, each holding
    // samples of its own part alone.
    let (panels, held) = patches_and_parts_held(split_plate("panel_right", "panel_left", 0.0));
    assert_eq!(panels.len(), 48);
    assert!(held.iter().any(|(_, parts)| parts.len() == 2), "a display spans the two panels");
    for (patch, (_, parts)) in panels.iter().zip(&held) {
        assert_eq!(
            &patch.covers, parts,
            "{}: the parts it covers are the parts its samples lie on",
            patch.name
        );
    }

    let (beside_glass, held) = patches_and_parts_held(split_plate("panel", "window", 0.0));
    let mut columns: Vec<String> = beside_glass.iter().map(|p| format!("{:.2}", p.centre.y)).collect();
    columns.sort();
    columns.dedup();
    assert_eq!(columns, ["-0.25", "0.25"], "{:?}", held);
    assert_eq!(beside_glass.len(), 16);
    for ((name, parts), patch) in held.iter().zip(&beside_glass) {
        let own = name.split('@').next().unwrap();
        assert_eq!(parts, &[own.to_string()], "{name} holds {parts:?}");
        assert_eq!(patch.covers, [own.to_string()], "{name} covers {:?}", patch.covers);
    }
}

#[test]
fn a_display_reaching_over_a_window_by_a_twentieth_is_no_candidate() {
    // The plate cut at y = 0.03. Centred at y = −0.15, a 0.40 m display
    // spans −0.35 to 0.05: 95 % of it on the panel, enough to fit, and 5 %
    // over the window, so it would hide the glass's edge: no candidate (it
    // was one). Kept: the columns y = ∓0.25, wholly on their part. Two body
    // panels cut there keep all 48, those across the seam covering both.
    let (beside_glass, _) = patches_and_parts_held(split_plate("panel", "window", 0.03));
    let mut columns: Vec<String> = beside_glass.iter().map(|p| format!("{:.2}", p.centre.y)).collect();
    columns.sort();
    columns.dedup();
    assert_eq!(columns, ["-0.25", "0.25"]);
    assert_eq!(beside_glass.len(), 16);
    let (panels, _) = patches_and_parts_held(split_plate("panel_right", "panel_left", 0.03));
    assert_eq!(panels.len(), 48);
    let spanning = panels.iter().filter(|p| p.covers == ["panel_left", "panel_right"]).count();
    // Columns −0.15, −0.05, 0.05 and 0.15 reach across y = 0.03; 8 rows each.
    assert_eq!(spanning, 32);
}

#[test]
fn glass_hidden_behind_the_panel_leaves_its_displays_and_glass_beside_it_does_not() {
    // The plate of `a_flat_plate_holds_the_patches_that_fit_on_it_exactly`
    // (48 patches) with a window 3 cm behind it, as a door's glass may run
    // inside the door: the window does not show under any panel display
    // (each box reaches 7.5 cm behind its plane), so the panel keeps its 48,
    // each covering the panel alone (they were dropped), and the window, seen
    // from its own side, keeps 48 too. A window 3 cm behind the panel and
    // 0.5 m beside it, cut at y = 0.03 as in
    // `a_display_reaching_over_a_window_by_a_twentieth_is_no_candidate`,
    // shows beside the panel's edge: the same 16 as there.
    let window_behind = |from: f32| {
        let mut mesh = plate(1.0, 1.0, 2.0);
        let corner = |y: f32, z: f32| Vec3::new(-0.03, y, z);
        mesh.add_quad("window", corner(from, 1.5), corner(0.5, 1.5), corner(0.5, 2.5), corner(from, 2.5));
        mesh
    };
    let (patches, parts_held) = patches_and_parts_held(window_behind(-0.5));
    let on = |part: &str| patches.iter().filter(|p| p.name.starts_with(&format!("{part}@"))).count();
    assert_eq!(
        (on("plate"), on("window")),
        (48, 48),
        "{:?}",
        patches.iter().map(|p| &p.name).collect::<Vec<_>>()
    );
    for (patch, (_, held)) in patches.iter().zip(&parts_held) {
        let part = patch.name.split('@').next().unwrap();
        assert_eq!(
            (patch.covers.as_slice(), held.as_slice()),
            ([part.to_string()].as_slice(), [part.to_string()].as_slice())
        );
    }
    let mut beside = split_plate("panel", "window", 0.03);
    let corner = |y: f32, z: f32| Vec3::new(-0.03, y, z);
    beside.add_quad("window", corner(-0.5, 1.5), corner(0.03, 1.5), corner(0.03, 2.5), corner(-0.5, 2.5));
    let (panel, _) = patches_and_parts_held(beside);
    let panel: Vec<&PlacedPatch> = panel.iter().filter(|p| p.name.starts_with("panel@")).collect();
    assert_eq!(
        panel.len(),
        8,
        "the column y = −0.25 only: {:?}",
        panel.iter().map(|p| &p.name).collect::<Vec<_>>()
    );
}

/// The demo truck and every family body at its typical dimensions, named.
fn truck_and_family_bodies() -> Vec<(String, Mesh)> {
    let mut bodies = vec![("demo truck".to_string(), Scene::demo().vehicle)];
    for body in crate::scene::family::BodyType::ALL {
        let mesh =
            crate::scene::family::body_mesh(body, &crate::scene::family::BodyDims::typical(body)).unwrap();
        bodies.push((body.name().to_string(), mesh));
    }
    bodies
}

#[test]
fn no_patch_of_the_truck_or_a_family_body_mixes_mountable_surface_with_glass_or_wheels() {
    // Before, 7–15 % of their patches did: a trunk-lid display 35 % over the
    // rear window, a bed-side display 17 % over the tyre, named for (and
    // judged mountable by) the part at their centres.
    // The footprint's surface too: each part a display covers is of its kind.
    let not_mountable = ufcsr::placement::default_not_mountable();
    for (body, mesh) in truck_and_family_bodies() {
        let scene = scene_with(mesh, Occluders::default());
        let obstacles = Obstacles::new(&scene);
        let samples = samples_of(&scene.vehicle, [512, 512]);
        let patches = place_patches(&inputs(&scene, &samples, &obstacles), [0.40, 0.15], 0.10);
        assert!(patches.len() > 500, "{body}: {} patches", patches.len());
        let mesh = &scene.vehicle;
        for patch in &patches {
            let own = ufcsr::placement::mountable(&patch.name, &not_mountable);
            let part = patch.name.split('@').next().unwrap();
            assert!(patch.covers.iter().any(|c| c == part), "{body}: {} covers its own part", patch.name);
            for covered in &patch.covers {
                let kind = ufcsr::placement::mountable(covered, &not_mountable);
                assert_eq!(kind, own, "{body}: {} covers {covered}", patch.name);
            }
            for &m in &patch.members {
                let part =
                    &mesh.parts[mesh.triangle_part[samples.samples[m as usize].triangle as usize] as usize];
                assert_eq!(
                    ufcsr::placement::mountable(part, &not_mountable),
                    own,
                    "{body}: {} holds surface of {part}",
                    patch.name
                );
            }
        }
    }
}

/// The demo truck's samples: `fraction` of the texels of a `palette`
/// unwrap, seeded `seed`, K × K per texel.
fn demo_samples(mesh: &Mesh, palette: [u32; 2], fraction: f64, seed: u64, k: u32) -> SurfaceSamples {
    let unwrapped = unwrap_islands_avoiding(mesh, palette, background_texel(palette)).unwrap();
    surface_samples(mesh, &unwrapped, fraction, seed, k)
}

#[test]
fn the_patch_layout_is_the_same_whatever_the_texel_sample() {
    // Issue 36: units of a design each measure their own texel sample; their
    // displays are one candidate only if the layout follows the mesh alone.
    let scene = scene_with(Scene::demo().vehicle, Occluders::default());
    let obstacles = Obstacles::new(&scene);
    let layout = |samples: &SurfaceSamples| {
        let patches = place_patches(&inputs(&scene, samples, &obstacles), [0.40, 0.15], 0.10);
        let members: usize = patches.iter().map(|p| p.members.len()).sum();
        let layout: Vec<_> =
            patches.into_iter().map(|p| (p.name, p.mirror, p.centre, p.normal, p.up)).collect();
        (layout, members)
    };
    let (all, all_members) = layout(&demo_samples(&scene.vehicle, [512, 512], 1.0, 1, 1));
    assert!(all.len() > 100, "{} patches", all.len());
    assert!(all.iter().filter(|p| p.1.is_some()).count() > all.len() / 2, "most patches have a mirror");
    for (palette, fraction, seed, k) in
        [([512, 512], 0.25, 7, 1), ([1024, 1024], 0.5, 3, 2), ([256, 256], 1.0, 1, 1)]
    {
        let (other, members) = layout(&demo_samples(&scene.vehicle, palette, fraction, seed, k));
        assert_eq!(other, all, "{palette:?} at {fraction} seeded {seed}, K = {k}");
        assert_ne!(members, all_members, "the members do follow the sample");
    }
}

/// The candidates of `mesh` as the analyzer's published places see them:
/// every part, and every 0.40 m × 0.15 m display patch with its centre.
fn named_candidates(mesh: Mesh) -> Vec<(String, ufcsr::placement::CandidateKind, Option<[f64; 3]>)> {
    let scene = scene_with(mesh, Occluders::default());
    let obstacles = Obstacles::new(&scene);
    let samples = samples_of(&scene.vehicle, [512, 512]);
    let patches = place_patches(&inputs(&scene, &samples, &obstacles), [0.40, 0.15], 0.10);
    let parts = scene.vehicle.parts.iter().map(|p| (p.clone(), ufcsr::placement::CandidateKind::Part, None));
    let patches = patches
        .into_iter()
        .map(|p| (p.name, ufcsr::placement::CandidateKind::Patch, Some(p.centre.to_array())));
    parts.chain(patches).collect()
}

#[test]
fn every_published_place_is_a_named_candidate_on_the_truck_and_every_family_body() {
    // Issue 42 §7: the places eHMI studies tested are scored on every body,
    // so each must be a part of each, and a display patch wherever a
    // 0.40 m × 0.15 m display fits.
    for (body, mesh) in truck_and_family_bodies() {
        let candidates = named_candidates(mesh);
        let keyed: Vec<(&str, ufcsr::placement::CandidateKind, Option<[f64; 3]>)> =
            candidates.iter().map(|(n, k, c)| (n.as_str(), *k, *c)).collect();
        for place in ufcsr::placement::PUBLISHED_LOCATIONS {
            let members = place.members(&keyed);
            let count = |kind: ufcsr::placement::CandidateKind| {
                members.iter().filter(|&&i| keyed[i].1 == kind).count()
            };
            let (parts, patches) =
                (count(ufcsr::placement::CandidateKind::Part), count(ufcsr::placement::CandidateKind::Patch));
            eprintln!("{body}: {}: {parts} parts, {patches} patches", place.name);
            assert!(parts >= 1, "{body}: no part is the {}", place.name);
            // No 0.40 m display fits a 0.2 m mirror, a headlight or a wheel at 90 %, nor the
            // sedan's and SUV's bumper (at most 30 % of the front panel's height).
            let fits = match place.name {
                "side mirrors" | "front wheels" | "headlights" => false,
                "bumper" => !matches!(body.as_str(), "sedan" | "suv"),
                _ => true,
            };
            assert!(!fits || patches >= 1, "{body}: no display patch at the {}", place.name);
        }
    }
}
