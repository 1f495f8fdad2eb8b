//! Which options a command's `--help` shows. A researcher needs a handful of
//! options per command; the developer, benchmark and expert switches (PNG
//! encoder settings, culling and scissor switches, shards, kernel backends,
//! placement thresholds past the documented rule) stay accepted everywhere
//! but are listed only by `--help-all`, so that no command's help shows more
//! than 20 options and the whole tree no more than 70 (issue 45; held by the
//! tests below). The list is
//! one table, by long name, so a new switch is hidden by naming it here.

use std::ffi::OsString;

use crate::console::EXIT_STATUS_HELP;

/// Options shown by `--help-all` only (long names, without the dashes).
pub(crate) const ADVANCED: [&str; 36] = [
    // capture: the encoder, the renderer's switches, benchmark and plumbing
    "png-compression",
    "tile-filter",
    "keep-background-tiles",
    "no-cull",
    "no-scissor",
    "backend",
    "shard",
    "texel-samples",
    "patch-spacing",
    "views-scale",
    "keep-uvs",
    "palette",
    "parts",
    "program",
    // analysis: palette images, background colours, paper-compatible columns, batch modes
    "fcsp",
    "background",
    "dedupe",
    "csv-style",
    "strict",
    "no-manifest",
    "each",
    "solo-camera",
    "ignore-solo",
    // placement: thresholds past the documented rule (placement.md lists them)
    "region-radius-m",
    "epsilon-s",
    "max-view-angle-deg",
    "decision-window-s",
    "eyes",
    "min-solid-angle-sr",
    // study and observers: the old grid and the resolution check's knobs
    "no-exact",
    "resolution-check",
    "safety-factor",
    "display-sample",
    "heights",
    "eye-heights",
    "positions",
];

/// The word that lists every option of a command.
pub(crate) const HELP_ALL: &str = "--help-all";

/// What a command's help says when it hides options.
const MORE: &str = "More options (developer, benchmark and expert switches): add --help-all.";

/// `command` and every command below it with the [`ADVANCED`] options hidden
/// and a line saying how to see them (under the exit codes).
pub(crate) fn hide_advanced(command: clap::Command) -> clap::Command {
    let hides = command.get_arguments().any(is_advanced);
    let command = command.mut_args(|arg| if is_advanced(&arg) { arg.hide(true) } else { arg });
    let command = if hides { command.after_help(format!("{EXIT_STATUS_HELP}\n\n{MORE}")) } else { command };
    command.mut_subcommands(hide_advanced)
}

fn is_advanced(arg: &clap::Arg) -> bool {
    arg.get_long().is_some_and(|long| ADVANCED.contains(&long))
}

/// True when the command line asks for `--help-all` (before a `--`); the
/// arguments then ask for `--help` instead, of the tree with nothing hidden.
pub(crate) fn take_help_all(args: &mut [OsString]) -> bool {
    let end = args.iter().position(|arg| arg == "--").unwrap_or(args.len());
    let mut found = false;
    for arg in &mut args[1..end.max(1)] {
        if arg == HELP_ALL {
            *arg = OsString::from("--help");
            found = true;
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use super::*;
    use crate::program::Program;

    /// The most options one command's `--help` lists (its own and the global ones).
    const MAX_VISIBLE_PER_COMMAND: usize = 20;
    /// The most distinct options the whole `--help` tree lists.
    const MAX_VISIBLE_DISTINCT: usize = 70;

    /// Every command of the tree (built, so global options are on each) with the
    /// long options its help lists.
    fn visible(command: &clap::Command, path: &str, out: &mut Vec<(String, Vec<String>)>) {
        let longs = command
            .get_arguments()
            .filter(|arg| !arg.is_hide_set())
            .filter_map(|arg| arg.get_long())
            .filter(|long| !matches!(*long, "help" | "version"))
            .map(str::to_string)
            .collect();
        out.push((path.to_string(), longs));
        for sub in command.get_subcommands().filter(|sub| sub.get_name() != "help") {
            visible(sub, &format!("{path} {}", sub.get_name()), out);
        }
    }

    fn tree(mut command: clap::Command) -> Vec<(String, Vec<String>)> {
        command.build();
        let mut out = Vec::new();
        visible(&command, "ufcsr", &mut out);
        out
    }

    #[test]
    fn no_help_lists_more_than_20_options_and_the_tree_at_most_70() {
        let commands = tree(Program::Ufcsr.command());
        let mut distinct = BTreeSet::new();
        for (path, longs) in &commands {
            assert!(
                longs.len() <= MAX_VISIBLE_PER_COMMAND,
                "`{path} --help` lists {}: {longs:?}",
                longs.len()
            );
            distinct.extend(longs.iter().cloned());
        }
        assert!(distinct.len() <= MAX_VISIBLE_DISTINCT, "{} distinct options: {distinct:?}", distinct.len());
    }

    #[test]
    fn help_all_lists_every_hidden_option_and_each_hidden_name_is_an_option() {
        let all: BTreeSet<String> =
            tree(Program::Ufcsr.command_all()).into_iter().flat_map(|(_, longs)| longs).collect();
        for name in ADVANCED {
            assert!(all.contains(name), "--{name} is in ADVANCED but no command has it");
        }
        let shown: BTreeSet<String> =
            tree(Program::Ufcsr.command()).into_iter().flat_map(|(_, longs)| longs).collect();
        assert!(ADVANCED.iter().all(|name| !shown.contains(*name)), "an ADVANCED option is still shown");
        let mut demo = Program::Ufcsr.command();
        let help = demo.find_subcommand_mut("capture").unwrap().find_subcommand_mut("demo").unwrap();
        assert!(help.render_help().to_string().contains(MORE));
    }

    #[test]
    fn help_all_is_read_as_help_before_a_double_dash_only() {
        let mut args: Vec<OsString> = ["ufcsr", "analyze", "--help-all"].map(OsString::from).to_vec();
        assert!(take_help_all(&mut args));
        assert_eq!(args[2], "--help");
        let mut after: Vec<OsString> = ["ufcsr", "analyze", "--", "--help-all"].map(OsString::from).to_vec();
        assert!(!take_help_all(&mut after));
        assert_eq!(after[3], "--help-all");
    }
}
