//! The libraries' option enums as command-line choices: each mirrors one
//! library enum variant for variant (its help text is the variant's doc,
//! its words clap's kebab-case names) and converts into it, so parsing goes
//! one way — clap here, plain enums in `ufcsr` and `ufcsr_capture`, which
//! know nothing of clap.

/// A choice enum mirroring `$target` variant for variant, and its conversion.
macro_rules! mirror {
    ($(#[$meta:meta])* $name:ident => $target:path { $($(#[$variant_meta:meta])* $variant:ident,)* }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
        pub enum $name {
            $($(#[$variant_meta])* $variant,)*
        }

        impl From<$name> for $target {
            fn from(choice: $name) -> $target {
                match choice {
                    $($name::$variant => <$target>::$variant,)*
                }
            }
        }
    };
}

mirror! {
    /// What one count means ([`ufcsr::Dedupe`]).
    Dedupe => ufcsr::Dedupe {
        /// A texel counts once per image (tile) that shows it.
        Image,
        /// A texel counts once per eye-frame, however many of its tiles show it
        /// (each eye counts separately).
        Frame,
        /// A texel counts once per frame, over both eyes and all their tiles.
        EyePair,
    }
}

mirror! {
    /// How counts map onto the colormap ([`ufcsr::Scale`]).
    Scale => ufcsr::Scale {
        /// `count / max`.
        Linear,
        /// `ln(1 + count) / ln(1 + max)`: shows rarely seen texels too.
        Log,
    }
}

mirror! {
    /// Which eyes must read a candidate for a frame to count ([`ufcsr::placement::EyeRule`]).
    EyeRule => ufcsr::placement::EyeRule {
        /// Either eye (the default).
        Any,
        /// Every eye of the archive.
        Both,
    }
}

mirror! {
    /// Columns of `parts.csv` ([`ufcsr::output::CsvStyle`]).
    CsvStyle => ufcsr::output::CsvStyle {
        Report,
        Paper,
    }
}

/// Which figures an analysis draws (`--figures`; [`ufcsr::output::Figures`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FiguresChoice {
    /// Each figure once: a plot as two-column PNG and PDF, the views as their sheet.
    On,
    /// Also the variants: each plot as SVG and at one column, each view alone in `views/`.
    All,
    /// No figures (the tables are the same).
    Off,
}

impl From<FiguresChoice> for ufcsr::output::Figures {
    fn from(choice: FiguresChoice) -> ufcsr::output::Figures {
        match choice {
            FiguresChoice::On => ufcsr::output::Figures::All,
            FiguresChoice::All => ufcsr::output::Figures::WithVariants,
            FiguresChoice::Off => ufcsr::output::Figures::None,
        }
    }
}

#[cfg(feature = "capture")]
pub(crate) use capture::*;

/// The capture's choices (behind the `capture` feature, as the capture is).
#[cfg(feature = "capture")]
mod capture {
    mirror! {
        /// Which GPU backend to try ([`ufcsr_capture::Backend`]).
        Backend => ufcsr_capture::Backend {
            /// Vulkan, then GL.
            Auto,
            #[value(alias = "vk")]
            Vulkan,
            #[value(aliases = ["gles", "opengl"])]
            Gl,
        }
    }

    mirror! {
        /// PNG compression of tiles ([`ufcsr_capture::Compression`]).
        Compression => ufcsr_capture::Compression {
            Fastest,
            /// The default: much faster to encode than `balanced`, for somewhat larger files.
            Fast,
            #[value(alias = "default")]
            Balanced,
            #[value(alias = "best")]
            High,
        }
    }

    mirror! {
        /// The PNG row filter of tiles ([`ufcsr_capture::TileFilter`]).
        TileFilter => ufcsr_capture::TileFilter {
            /// Every row Up-filtered: fast to decode, a little larger.
            Up,
            /// The png crate's per-row choice (mostly Paeth): smaller, slower to decode.
            Adaptive,
        }
    }

    mirror! {
        /// Traffic for the demo ([`ufcsr_capture::scene::DemoTraffic`]): a second pickup, the truck's twin.
        DemoTraffic => ufcsr_capture::scene::DemoTraffic {
            /// Beside the truck, a lane to the side of the pedestrian and 2 m ahead (the
            /// multiple-threat crossing).
            AdjacentLane,
            /// Ahead of the truck in its lane.
            LeadCar,
        }
    }

    mirror! {
        /// A body of the parametric family ([`ufcsr_capture::scene::BodyType`]; docs/vehicles.md).
        BodyType => ufcsr_capture::scene::BodyType {
            Sedan,
            Suv,
            Van,
            Pickup,
            Bus,
        }
    }

    mirror! {
        /// What a study compares ([`ufcsr_capture::study::StudyMeasure`]).
        StudyMeasure => ufcsr_capture::study::StudyMeasure {
            /// The paper's count, once per eye-frame (texels seen per eye-frame) ↔
            /// any-part visibility.
            Count,
            /// Visible angular area (solid angle of the pixels) ↔ the ray-traced
            /// solid angle.
            AngularArea,
        }
    }
}

/// A switch given as `on` or `off`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Switch {
    On,
    Off,
}
