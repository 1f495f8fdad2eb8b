//! Which vector code this process runs: one choice for the whole process
//! (the tile decoder's unfilter and the counting kernels alike), made once
//! from what the CPU has and capped by `UFCSR_KERNEL`, recorded as `kernel`
//! in `timings.json`.
//!
//! A kernel is chosen only where the CPU has every feature its code is
//! compiled for: each `#[target_feature(enable = …)]` in this folder names
//! only features of its kernel's list ([`AVX2_FEATURES`],
//! [`AVX512_FEATURES`]), a unit test holds them to it, and detection checks
//! the whole list. That is what makes calling the kernels sound, so it
//! lives here, beside the only code that may be `unsafe`.

/// Environment variable that caps the kernel: `portable` or `avx2` (for
/// comparisons, or to rule the vector code out when debugging). Results are
/// identical whatever the kernel.
pub const KERNEL_ENV: &str = "UFCSR_KERNEL";

/// Which row kernels (and count updates) this process uses, slowest first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Kernel {
    /// Plain Rust, every CPU.
    Portable,
    /// 8 pixels per instruction (x86-64 with AVX2, BMI1/2 and POPCNT).
    Avx2,
    /// 16 pixels per instruction (x86-64 with AVX-512 F, BW and VBMI, and
    /// everything AVX2 needs: the AVX-512 kernel falls back to the AVX2
    /// unfilter for groups of fewer than eight rows).
    Avx512,
}

/// Every CPU feature the AVX2 kernels are compiled for.
pub(crate) const AVX2_FEATURES: &[&str] = &["avx2", "popcnt", "bmi1", "bmi2"];

/// Every CPU feature the AVX-512 kernels are compiled for, and the AVX2
/// kernels' (which run on the AVX-512 kernel's strength).
pub(crate) const AVX512_FEATURES: &[&str] =
    &["avx512f", "avx512bw", "avx512vbmi", "avx2", "popcnt", "bmi1", "bmi2"];

impl Kernel {
    /// Its name, as [`KERNEL_ENV`] accepts it.
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Portable => "portable",
            Kernel::Avx2 => "avx2",
            Kernel::Avx512 => "avx512",
        }
    }

    /// The kernel named `name` (as [`Kernel::name`] writes it).
    pub fn from_name(name: &str) -> Option<Kernel> {
        [Kernel::Portable, Kernel::Avx2, Kernel::Avx512].into_iter().find(|kernel| kernel.name() == name)
    }

    /// The CPU features its code is compiled for (none for the portable one).
    pub(crate) fn features(self) -> &'static [&'static str] {
        match self {
            Kernel::Portable => &[],
            Kernel::Avx2 => AVX2_FEATURES,
            Kernel::Avx512 => AVX512_FEATURES,
        }
    }

    /// The best kernel this CPU can run (detected once): the fastest whose
    /// every feature the CPU has.
    pub fn supported() -> Kernel {
        static SUPPORTED: std::sync::OnceLock<Kernel> = std::sync::OnceLock::new();
        *SUPPORTED.get_or_init(|| {
            [Kernel::Avx512, Kernel::Avx2]
                .into_iter()
                .find(|kernel| kernel.features().iter().all(|&feature| detected(feature) == Some(true)))
                .unwrap_or(Kernel::Portable)
        })
    }

    /// The value of [`KERNEL_ENV`] when it names no kernel (for a warning).
    pub fn unknown_request() -> Option<String> {
        let value = std::env::var(KERNEL_ENV).ok()?;
        (!value.is_empty() && Kernel::from_name(&value).is_none()).then_some(value)
    }

    /// The kernel in use: [`Kernel::supported`], capped by [`KERNEL_ENV`].
    pub fn selected() -> Kernel {
        static SELECTED: std::sync::OnceLock<Kernel> = std::sync::OnceLock::new();
        *SELECTED.get_or_init(|| {
            let cap = std::env::var(KERNEL_ENV).ok().and_then(|name| Kernel::from_name(&name));
            let supported = Kernel::supported();
            cap.map_or(supported, |cap| cap.min(supported))
        })
    }
}

/// Whether this CPU has `feature` (a name of the kernels' lists); `None`
/// for a name this function does not know (or on another architecture),
/// which rules its kernel out.
fn detected(feature: &str) -> Option<bool> {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::is_x86_feature_detected as has;
        Some(match feature {
            "avx2" => has!("avx2"),
            "avx512f" => has!("avx512f"),
            "avx512bw" => has!("avx512bw"),
            "avx512vbmi" => has!("avx512vbmi"),
            "bmi1" => has!("bmi1"),
            "bmi2" => has!("bmi2"),
            "popcnt" => has!("popcnt"),
            _ => return None,
        })
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = feature;
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `(file, kernel, features)` for each `#[target_feature(enable = …)]`
    /// under `src/simd/`: the kernel is the one the file's name or the
    /// function's name says (`avx512` before `avx2`).
    fn enabled_features() -> Vec<(String, Kernel, Vec<String>)> {
        let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/simd");
        let mut files = vec![folder.clone()];
        let mut found = Vec::new();
        while let Some(path) = files.pop() {
            if path.is_dir() {
                files.extend(std::fs::read_dir(&path).unwrap().map(|entry| entry.unwrap().path()));
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let name = path.strip_prefix(&folder).unwrap().display().to_string();
            let mut rest = text.as_str();
            while let Some(at) = rest.find("#[target_feature(enable = \"") {
                rest = &rest[at + "#[target_feature(enable = \"".len()..];
                let features: Vec<String> =
                    rest[..rest.find('"').unwrap()].split(',').map(|f| f.trim().to_string()).collect();
                let function = &rest[rest.find("fn ").unwrap()..];
                let function = &function[..function.find('(').unwrap()];
                let says = |word: &str| name.contains(word) || function.contains(word);
                let kernel = if says("avx512") {
                    Kernel::Avx512
                } else {
                    assert!(says("avx2"), "{name}: `{function}` names no kernel");
                    Kernel::Avx2
                };
                found.push((format!("{name}: {function}"), kernel, features));
            }
        }
        found
    }

    #[test]
    fn detection_checks_every_feature_the_kernels_are_compiled_for() {
        let enabled = enabled_features();
        assert!(enabled.len() >= 10, "the kernels' functions were not found: {enabled:?}");
        for (function, kernel, features) in enabled {
            for feature in features {
                assert!(kernel.features().contains(&feature.as_str()), "{function} enables {feature}");
            }
        }
        // The AVX-512 kernel runs AVX2 code too.
        assert!(AVX2_FEATURES.iter().all(|feature| AVX512_FEATURES.contains(feature)));
        #[cfg(target_arch = "x86_64")]
        for feature in AVX512_FEATURES {
            assert!(detected(feature).is_some(), "detection does not know {feature}");
        }
    }

    #[test]
    fn names_round_trip() {
        for kernel in [Kernel::Portable, Kernel::Avx2, Kernel::Avx512] {
            assert_eq!(Kernel::from_name(kernel.name()), Some(kernel));
        }
        assert_eq!(Kernel::from_name("avx1024"), None);
        assert!(Kernel::selected() <= Kernel::supported());
    }
}
