//! What a capture-like command measures, named one way everywhere (issue 45
//! §4): `demo`, `scene FILE` or `unity FILE`, as after `ufcsr capture`. The
//! captures take these words as subcommands; `where`, `study` and `observers`
//! take them as their first arguments ([`SourceArgs`]), and each resolves them
//! here ([`Source`]), so a scene is loaded, and a word refused, the same way
//! in every command. The older `study FILE.json` (a scene file without the
//! word `scene`) still works and is not shown.

use std::path::PathBuf;

use clap::Args;
use ufcsr_capture::Scene;

use crate::choices::{BodyType, DemoTraffic};

/// What is measured: the built-in demo (its truck, a family body, or the
/// truck with traffic), a scene file or a Unity export.
#[derive(Clone)]
pub(crate) enum Source {
    /// The built-in demo: with `body`, a family body in place of the truck;
    /// with `traffic`, the truck's twin in traffic.
    Demo { traffic: Option<DemoTraffic>, body: Option<BodyType> },
    /// A scene file.
    Scene(PathBuf),
    /// A Unity scenario export, replayed with the demo truck.
    Unity(PathBuf),
}

impl Source {
    /// The scene: for the demo with traffic, the demo itself (each
    /// scenario's scene with traffic is built where it is captured,
    /// [`ufcsr_capture::Scene::demo_with_traffic`]; it has the demo's
    /// scenarios and rig).
    pub(crate) fn scene(&self) -> anyhow::Result<Scene> {
        Ok(match self {
            Source::Demo { body: Some(body), .. } => {
                let body = ufcsr_capture::scene::BodyType::from(*body);
                Scene::demo_with_body(body, &ufcsr_capture::scene::BodyDims::typical(body))?
            }
            Source::Demo { .. } => Scene::demo(),
            Source::Scene(file) => Scene::load(file)?,
            Source::Unity(file) => Scene::unity(file)?,
        })
    }

    /// How the answer names it: `demo`, `demo --body van`, `scene FILE`, …
    pub(crate) fn describe(&self) -> String {
        match self {
            Source::Demo { traffic: Some(traffic), .. } => format!("demo --traffic {}", choice(*traffic)),
            Source::Demo { body: Some(body), .. } => format!("demo --body {}", choice(*body)),
            Source::Demo { .. } => "demo".to_string(),
            Source::Scene(file) => format!("scene {}", file.display()),
            Source::Unity(file) => format!("unity {}", file.display()),
        }
    }
}

/// A choice's word on the command line.
fn choice(value: impl clap::ValueEnum) -> String {
    value.to_possible_value().map_or_else(String::new, |value| value.get_name().to_string())
}

/// What is measured, as a command's first arguments: `demo`, `scene FILE`
/// or `unity FILE` (the words of `ufcsr capture`).
#[derive(Args, Clone)]
pub(crate) struct SourceArgs {
    /// What to measure, as after `ufcsr capture`: `demo` (the built-in pickup and its
    /// scenarios A–D), `scene FILE` (a scene file) or `unity FILE` (a Unity export, replayed
    /// with the demo truck).
    #[arg(value_name = "demo|scene|unity")]
    source: String,
    /// The scene file (after `scene`) or the Unity export (after `unity`).
    #[arg(value_name = "FILE")]
    file: Option<PathBuf>,
}

impl SourceArgs {
    /// The source the words name; `demo` with neither a body nor traffic.
    pub(crate) fn source(&self) -> anyhow::Result<Source> {
        self.source_with(None, None)
    }

    /// The source the words name, the demo with `traffic` or `body` (refused
    /// for a scene file or a Unity export, which bring their own vehicle).
    pub(crate) fn source_with(
        &self,
        traffic: Option<DemoTraffic>,
        body: Option<BodyType>,
    ) -> anyhow::Result<Source> {
        let word = self.source.as_str();
        let source = match (word, &self.file) {
            ("demo", None) => Source::Demo { traffic, body },
            ("demo", Some(file)) => anyhow::bail!(
                "`demo` takes no file (got {}); for a scene file write `scene {}`",
                file.display(),
                file.display()
            ),
            ("scene", Some(file)) => Source::Scene(file.clone()),
            ("unity", Some(file)) => Source::Unity(file.clone()),
            ("scene" | "unity", None) => anyhow::bail!("`{word}` needs a file: `{word} FILE`"),
            // The older form: a scene file without the word `scene`.
            (_, None) => Source::Scene(PathBuf::from(word)),
            (_, Some(_)) => {
                anyhow::bail!("`{word}` names nothing to measure: write `demo`, `scene FILE` or `unity FILE`")
            }
        };
        if !matches!(source, Source::Demo { .. }) && (traffic.is_some() || body.is_some()) {
            anyhow::bail!(
                "--traffic and --body are for the demo; a scene file sets its own vehicle and traffic"
            );
        }
        Ok(source)
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    fn words(source: &str, file: Option<&str>) -> SourceArgs {
        SourceArgs { source: source.into(), file: file.map(PathBuf::from) }
    }

    #[test]
    fn the_scene_is_named_as_after_capture_and_the_older_file_form_still_works() {
        assert!(matches!(words("demo", None).source().unwrap(), Source::Demo { traffic: None, body: None }));
        assert!(
            matches!(words("scene", Some("s.json")).source().unwrap(), Source::Scene(f) if f == Path::new("s.json"))
        );
        assert!(
            matches!(words("unity", Some("u.json")).source().unwrap(), Source::Unity(f) if f == Path::new("u.json"))
        );
        assert!(
            matches!(words("s.json", None).source().unwrap(), Source::Scene(f) if f == Path::new("s.json"))
        );
        let error = |w: SourceArgs| w.source().err().expect("an error").to_string();
        assert!(error(words("scene", None)).contains("`scene FILE`"));
        assert!(error(words("demo", Some("s.json"))).contains("`scene s.json`"));
        assert!(error(words("s.json", Some("t.json"))).contains("`demo`, `scene FILE` or `unity FILE`"));
        let traffic = words("scene", Some("s.json")).source_with(Some(DemoTraffic::LeadCar), None);
        assert!(traffic.err().unwrap().to_string().contains("for the demo"));
    }
}
