//! The family's known answers: each body has its named parts and a bounding
//! box equal to its dimensions, no two of its triangles lie on one another,
//! and impossible dimensions are refused naming the field.

use super::*;
use crate::scene::shapes::coplanar_overlaps;

/// Parts every body has (the demo truck's vocabulary).
const COMMON: [&str; 28] = [
    "front_bumper",
    "grill",
    "hood",
    "windshield",
    "windshield_rail_left",
    "windshield_rail_right",
    "roof",
    "rear_window",
    "cab_shoulder",
    "front_fender_left",
    "front_fender_right",
    "rear_fender_left",
    "rear_fender_right",
    "door_front_right",
    "b_pillar_left",
    "window_front_left",
    "window_rear_right",
    "side_mirror_left",
    "side_mirror_right",
    "headlight_left",
    "headlight_right",
    "tail_light_left",
    "front_license_plate",
    "rear_license_plate",
    "rear_bumper",
    "tyre_front_left",
    "rim_rear_right",
    "wheel_arch_rear_left",
];

fn own_parts(body: BodyType) -> &'static [&'static str] {
    match body {
        BodyType::Sedan => {
            &["door_front_left", "door_rear_left", "quarter_panel_right", "trunk_lid", "rear_panel"]
        }
        BodyType::Suv => &["door_front_left", "door_rear_right", "quarter_panel_left", "tailgate"],
        BodyType::Van => &["door_front_left", "door_rear_right", "side_panel_left", "rear_doors"],
        BodyType::Pickup => {
            &["door_front_left", "door_rear_right", "bed_side_left", "truck_bed", "bed_rail", "tailgate"]
        }
        BodyType::Bus => &["side_panel_left", "side_panel_right", "rear_panel"],
    }
}

#[test]
fn names_and_parse_round_trip() {
    for body in BodyType::ALL {
        assert_eq!(BodyType::parse(body.name()), Some(body));
        assert_eq!(BodyType::parse(&body.name().to_uppercase()), Some(body));
    }
    assert_eq!(BodyType::parse("truck"), None);
}

#[test]
fn each_body_has_its_named_parts_and_a_bounding_box_equal_to_its_dims() {
    for body in BodyType::ALL {
        let dims = BodyDims::typical(body);
        let mesh = body_mesh(body, &dims).unwrap();
        mesh.check(body.name()).unwrap();
        for part in COMMON.iter().chain(own_parts(body)) {
            assert!(mesh.parts.iter().any(|p| p == part), "{}: missing {part}", body.name());
        }
        // Without the mirrors (which stand out, as on a real vehicle) the box is the dims.
        let mut body_only = Mesh::default();
        for t in 0..mesh.triangles.len() {
            let part = &mesh.parts[mesh.triangle_part[t] as usize];
            if !part.starts_with("side_mirror") {
                let [a, b, c] = mesh.corners(t);
                body_only.add_triangle(part, a, b, c);
            }
        }
        let (min, max) = body_only.bounds();
        let want_min = glam::dvec3(-dims.length_m / 2.0, -dims.width_m / 2.0, 0.0);
        let want_max = glam::dvec3(dims.length_m / 2.0, dims.width_m / 2.0, dims.height_m);
        // f32 vertices: within 0.1 mm.
        assert!((min - want_min).abs().max_element() < 1e-4, "{}: min {min}, want {want_min}", body.name());
        assert!((max - want_max).abs().max_element() < 1e-4, "{}: max {max}, want {want_max}", body.name());
        let (_, all_max) = mesh.bounds();
        assert!(all_max.y > want_max.y + 0.1, "{}: the mirrors stand out", body.name());
    }
}

#[test]
fn no_body_has_overlapping_coplanar_triangles() {
    for body in BodyType::ALL {
        let mut dims = BodyDims::typical(body);
        for variant in 0..2 {
            let overlaps = coplanar_overlaps(&body_mesh(body, &dims).unwrap());
            assert!(
                overlaps.is_empty(),
                "{} (variant {variant}): {} coplanar overlaps, e.g. {:?}",
                body.name(),
                overlaps.len(),
                &overlaps[..overlaps.len().min(5)]
            );
            // And with other dimensions of the same body: longer, lower, more raked.
            dims.length_m *= 1.1;
            dims.height_m *= 0.95;
            dims.windshield_rake_deg = (dims.windshield_rake_deg + 5.0).min(70.0);
        }
    }
}

#[test]
fn impossible_dims_are_refused_naming_the_field() {
    let sedan = BodyDims::typical(BodyType::Sedan);
    let cases: [(&str, BodyDims); 9] = [
        ("length_m", BodyDims { length_m: f64::NAN, ..sedan }),
        ("width_m", BodyDims { width_m: -1.8, ..sedan }),
        ("height_m", BodyDims { height_m: 0.0, ..sedan }),
        ("bonnet_height_m", BodyDims { bonnet_height_m: 1.5, ..sedan }),
        ("bonnet_height_m", BodyDims { bonnet_height_m: 0.6, ..sedan }),
        ("windshield_rake_deg", BodyDims { windshield_rake_deg: 89.0, ..sedan }),
        ("windshield_rake_deg", BodyDims { windshield_rake_deg: 74.0, ..sedan }),
        ("wheelbase_m", BodyDims { wheelbase_m: 4.3, ..sedan }),
        ("length_m", BodyDims { length_m: 3.2, wheelbase_m: 2.2, bonnet_length_m: 0.9, ..sedan }),
    ];
    for (field, dims) in cases {
        let error = body_mesh(BodyType::Sedan, &dims).unwrap_err().to_string();
        assert!(error.contains(field) && error.contains("sedan"), "{field}: {error}");
    }
}
