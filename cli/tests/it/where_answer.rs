//! `ufcsr where` (issue 45 §3): one command from a scene to the placement
//! answer. It must give what the documented two steps give (`ufcsr capture …
//! --measure unobstructed --placement --display WxH`, then `ufcsr placement`),
//! print the rules it used and where its files are, and refuse a bad option
//! before it measures anything. Kept fast as the other capture tests are: a
//! 256² palette, two frames, a quarter of the texels.

use std::path::Path;
use std::process::{Command, Output};

/// The small setting every run here measures with.
const SMALL: [&str; 8] =
    ["--palette-size", "256", "--frames", "150,180", "--sample", "1/4", "--display", "0.5x0.3"];

fn ufcsr(cwd: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr")).args(args).current_dir(cwd).output().unwrap()
}

fn text(output: &Output) -> String {
    format!("{}\n{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr))
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
        .unwrap()
}

#[test]
fn where_answers_every_demo_scenario_with_its_rules_and_files_as_placement_does() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let output = ufcsr(cwd, &[&["where", "demo"][..], &SMALL, &["--symmetric", "--out", "W"]].concat());
    let said = text(&output);
    assert!(output.status.success(), "{said}");
    // The question and the rules it was answered under.
    assert!(said.contains("where should a 0.5x0.3 m display go on demo? scenarios A, B, C, D"), "{said}");
    assert!(said.contains("observer: a median US adult (eyes 1.57"), "{said}");
    assert!(said.contains("not mountable (scored, never chosen): wheel, wheels, tyre"), "{said}");
    assert!(said.contains("legible: characters of 0.5 of the display's height seen at 16 arcmin"), "{said}");
    // The answer, with an interval over the four scenarios, and its files.
    assert!(said.contains("best sets of at most k physical displays"), "{said}");
    assert!(said.contains("95 %"), "no interval over the scenarios: {said}");
    for scenario in ["A", "B", "C", "D"] {
        assert!(cwd.join(format!("W/runs/{scenario}/results/placement-frames.csv")).is_file(), "{scenario}");
    }
    assert!(said.contains(&format!("wrote {}", Path::new("W/answer/placement.json").display())), "{said}");
    assert!(
        said.contains("ufcsr capture demo --measure unobstructed --placement --display 0.5x0.3"),
        "{said}"
    );
    // The second step by hand gives the same placement.json, byte for byte in meaning.
    let runs = ["W/runs/A", "W/runs/B", "W/runs/C", "W/runs/D"];
    let by_hand =
        ufcsr(cwd, &[&["placement"][..], &runs, &["--k", "3", "--symmetric", "--out", "P"]].concat());
    assert!(by_hand.status.success(), "{}", text(&by_hand));
    assert_eq!(json(&cwd.join("W/answer/placement.json")), json(&cwd.join("P/placement.json")));
}

#[test]
fn the_two_commands_where_prints_give_the_same_answer() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let output = ufcsr(
        cwd,
        &[&["where", "demo", "--scenario", "b"][..], &SMALL, &["--k", "2", "--out", "W"]].concat(),
    );
    let said = text(&output);
    assert!(output.status.success(), "{said}");
    assert!(
        cwd.join("W/runs/B/results/placement-frames.csv").is_file(),
        "one scenario goes to runs/NAME too"
    );
    let steps: Vec<&str> = said
        .lines()
        .skip_while(|line| !line.starts_with("the same answer in two steps"))
        .skip(1)
        .take(2)
        .map(str::trim)
        .collect();
    assert_eq!(steps.len(), 2, "{said}");
    for step in &steps {
        // The printed words need no shell here (nothing in them is quoted).
        let words: Vec<String> = step.replace("W/", "H/").split_whitespace().map(String::from).collect();
        assert_eq!(words[0], "ufcsr");
        let words: Vec<&str> = words[1..].iter().map(String::as_str).collect();
        let ran = ufcsr(cwd, &words);
        assert!(ran.status.success(), "{step}: {}", text(&ran));
    }
    let frames =
        |root: &str| std::fs::read(cwd.join(root).join("runs/B/results/placement-frames.csv")).unwrap();
    assert!(frames("W") == frames("H"), "the printed capture measures another table");
    let combinations =
        |root: &str| json(&cwd.join(root).join("answer/placement.json"))["combinations"].clone();
    assert_eq!(combinations("W"), combinations("H"));
}

#[test]
fn where_refuses_a_bad_option_before_measuring_anything() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let cases: [(&[&str], &str); 6] = [
        (&["demo", "--k", "0"], "--k 0"),
        (&["demo", "--display", "0.4"], "0.4"),
        (&["demo", "--sample", "2"], "--sample 2"),
        (&["demo", "--scenario", "Z"], "Z"),
        (&["scene"], "`scene FILE`"),
        (&["scene", "x.json", "--traffic", "lead-car"], "for the demo"),
    ];
    for (args, named) in cases {
        let output = ufcsr(cwd, &[&["where"][..], args, &["--out", "W"]].concat());
        let said = text(&output);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {said}");
        assert!(said.contains(named), "{args:?} does not name {named}: {said}");
        assert!(!cwd.join("W").exists(), "{args:?} wrote W");
    }
}
