//! The vector kernels held to their portable references
//! ([`ufcsr::kernel_checks`]), in their own binary with its own harness
//! (`libtest-mimic`, `harness = false`) so that the choice to skip one is
//! made at run time: on a CPU without a check's kernel (AVX2, AVX-512) the
//! check is reported *ignored* with the reason, so `cargo test` counts it
//! among the ignored, never among the passed. Unlike `tests/external`, a
//! missing CPU feature is no failure under `CI`: CI machines may lack
//! AVX-512, and the portable kernel every CPU runs is tested anyway.
//! `cargo test -p ufcsr --test kernels unfilter` runs the unfilter's.

// Test and benchmark code may use std::fs directly; production code goes
// through the file layer (clippy.toml, docs/reliability.md).
#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

use libtest_mimic::{Arguments, Completion, Trial};
use ufcsr::Kernel;

fn main() {
    let arguments = Arguments::from_args();
    let supported = Kernel::supported();
    let trials = ufcsr::kernel_checks()
        .into_iter()
        .map(|check| {
            Trial::ignorable_test(check.name, move || {
                if check.kernel > supported {
                    let why = format!(
                        "needs the {} kernel; this CPU runs {}",
                        check.kernel.name(),
                        supported.name()
                    );
                    return Ok(Completion::ignored_with(why));
                }
                (check.run)();
                Ok(Completion::Completed)
            })
        })
        .collect();
    libtest_mimic::run(&arguments, trials).exit();
}
