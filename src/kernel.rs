//! Which vector code this process runs: one choice for the whole process
//! (the tile decoder's unfilter and the counting kernels alike), made once
//! from what the CPU has and capped by `UFCSR_KERNEL`, recorded as `kernel`
//! in `timings.json`. It lives below every folder that uses it, so the
//! decoder (`input`) need not reach up into the counting (`count`) for it.

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
    /// 16 pixels per instruction (x86-64 with AVX-512 F, BW and VBMI).
    Avx512,
}

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

    /// The best kernel this CPU can run (detected once).
    pub fn supported() -> Kernel {
        static SUPPORTED: std::sync::OnceLock<Kernel> = std::sync::OnceLock::new();
        *SUPPORTED.get_or_init(|| {
            #[cfg(target_arch = "x86_64")]
            {
                use std::arch::is_x86_feature_detected as has;
                let scalar = has!("popcnt") && has!("bmi1") && has!("bmi2");
                if scalar && has!("avx512f") && has!("avx512bw") && has!("avx512vbmi") {
                    return Kernel::Avx512;
                }
                if scalar && has!("avx2") {
                    return Kernel::Avx2;
                }
            }
            Kernel::Portable
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
