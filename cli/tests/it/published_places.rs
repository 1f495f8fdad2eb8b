//! `ufcsr-analyze placement` reports the places published eHMI studies
//! tested (issue 42 §7): on the shared placement fixture (`hood` legible
//! 0.7 s, `grill` 0.3 s) the console's "published locations" section and
//! `published-locations.csv` list every place, the hood and grille with
//! their known seconds and the places the vehicle lacks with none.

#[test]
fn placement_lists_every_published_place_on_the_console_and_in_its_csv() {
    let dir = tempfile::tempdir().unwrap();
    let archive = crate::common::placement_archive(dir.path(), "archive", false);
    let out = dir.path().join("placement");
    let output = crate::common::analyzer()
        .args(["placement".as_ref(), archive.as_os_str(), "--min-dwell-s".as_ref(), "0".as_ref()])
        .args(["--out".as_ref(), out.as_os_str()])
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let console = String::from_utf8_lossy(&output.stdout);
    assert!(console.contains("published locations"), "{console}");
    for place in ufcsr::placement::PUBLISHED_LOCATIONS {
        assert!(console.contains(&format!("  {} (", place.name)), "{} missing: {console}", place.name);
    }
    assert!(console.contains("legible 0.700 s") && console.contains("none on this vehicle"), "{console}");
    let csv = std::fs::read_to_string(out.join(ufcsr::placement::PUBLISHED_LOCATIONS_FILE)).unwrap();
    assert_eq!(csv.lines().count(), 1 + 2 * ufcsr::placement::PUBLISHED_LOCATIONS.len(), "{csv}");
    assert!(csv.lines().any(|l| l.starts_with("hood,") && l.contains(",part,1,hood,0.7")), "{csv}");
    assert!(csv.lines().any(|l| l.starts_with("grille,") && l.contains(",part,1,grill,0.3")), "{csv}");
    assert!(csv.lines().any(|l| l.starts_with("roof,") && l.contains(",part,0,,")), "{csv}");
}
