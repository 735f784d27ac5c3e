//! The instruction set the hot loops run with.
//!
//! The build's baseline is x86-64-v2 (SSE4.2; `.cargo/config.toml`). The tile rasterizer's quad
//! walk and the scene's fragment shader are compiled a second time for x86-64-v3 (AVX2, FMA,
//! BMI1/2, LZCNT, MOVBE), and that copy runs when the CPU has it ([`level`]). It is the same
//! source and the same arithmetic — Rust neither fuses `a·b + c` into one rounding nor
//! reorders float sums — in shorter code: three-operand forms, wider registers where the
//! compiler finds them. So the image bytes are the same at either level, which
//! `tests/cpu_levels.rs` checks.
//!
//! `TEXMAP_CPU=baseline` in the environment (or [`force`]) keeps every loop on the baseline,
//! to compare the two or to run the tests once without the second copy.

use std::sync::atomic::{AtomicU8, Ordering};

/// An instruction set the hot loops can run with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    /// The build's own target (x86-64-v2, or whatever another architecture builds for).
    Baseline,
    /// x86-64-v3: AVX2, FMA, BMI1, BMI2, LZCNT, MOVBE.
    V3,
}

/// The level in force: 0 until detected, then 1 + the level's index.
static LEVEL: AtomicU8 = AtomicU8::new(0);

impl Level {
    fn code(self) -> u8 {
        match self {
            Level::Baseline => 1,
            Level::V3 => 2,
        }
    }
}

/// The level the hot loops run with: [`Level::V3`] when the CPU has it and neither
/// `TEXMAP_CPU=baseline` nor [`force`] says otherwise (detected once, then a load).
#[inline]
#[must_use]
pub fn level() -> Level {
    match LEVEL.load(Ordering::Relaxed) {
        1 => Level::Baseline,
        2 => Level::V3,
        _ => detect(),
    }
}

/// Detects the level (the environment's word first) and keeps it.
#[cold]
fn detect() -> Level {
    let baseline = std::env::var_os("TEXMAP_CPU").is_some_and(|v| v == "baseline");
    let level = if !baseline && available(Level::V3) {
        Level::V3
    } else {
        Level::Baseline
    };
    LEVEL.store(level.code(), Ordering::Relaxed);
    level
}

/// Whether this CPU can run `level`.
#[must_use]
pub fn available(level: Level) -> bool {
    match level {
        Level::Baseline => true,
        #[cfg(target_arch = "x86_64")]
        Level::V3 => {
            std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
                && std::arch::is_x86_feature_detected!("bmi1")
                && std::arch::is_x86_feature_detected!("bmi2")
                && std::arch::is_x86_feature_detected!("lzcnt")
                && std::arch::is_x86_feature_detected!("movbe")
        }
        #[cfg(not(target_arch = "x86_64"))]
        Level::V3 => false,
    }
}

/// Runs the hot loops at `level` from now on, in the whole process, when the CPU can
/// (`None`: detect again). Returns the level in force.
pub fn force(level: Option<Level>) -> Level {
    match level {
        Some(l) if available(l) => {
            LEVEL.store(l.code(), Ordering::Relaxed);
            l
        }
        Some(_) => {
            LEVEL.store(Level::Baseline.code(), Ordering::Relaxed);
            Level::Baseline
        }
        None => detect(),
    }
}

/// Defines `$name`, which runs `$body` (an `#[inline(always)]` function of the same
/// arguments) compiled for x86-64-v3 when [`level`] says so, else as the baseline build has
/// it. The body inlines into either copy, with whatever it inlines in turn.
///
/// The baseline copy is a function of its own, not inlined into `$name`: inlined, its stack
/// frame was `$name`'s, allocated (and, past a page, probed page by page) on every call
/// before the level was looked at — `shade_batch`'s 41 KB, ten pages a batch, 2.2 % of the
/// trilinear plane's `perf` samples, though its x86-64-v3 copy ran.
macro_rules! dispatch {
    (
        $(#[$meta:meta])*
        $vis:vis fn $name:ident $(<$(const $c:ident: $ct:ty),*>)? ($($arg:ident: $ty:ty),* $(,)?)
            $(-> $ret:ty)? => $body:ident, $v3:ident
    ) => {
        $(#[$meta])*
        $vis fn $name $(<$(const $c: $ct),*>)? ($($arg: $ty),*) $(-> $ret)? {
            #[cfg_attr(target_arch = "x86_64", inline(never))]
            fn baseline $(<$(const $c: $ct),*>)? ($($arg: $ty),*) $(-> $ret)? {
                $body $(::<$($c),*>)? ($($arg),*)
            }
            #[cfg(target_arch = "x86_64")]
            if $crate::cpu::level() == $crate::cpu::Level::V3 {
                // SAFETY: the CPU has every feature `$v3` enables (`cpu::level`).
                return unsafe { $v3 $(::<$($c),*>)? ($($arg),*) };
            }
            baseline $(::<$($c),*>)? ($($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
        fn $v3 $(<$(const $c: $ct),*>)? ($($arg: $ty),*) $(-> $ret)? {
            $body $(::<$($c),*>)? ($($arg),*)
        }
    };
}
pub(crate) use dispatch;
