//! The vector instruction sets the lane loops ([`super::interp`]) are built for,
//! and the dispatch that calls the build [`Isa::detect`] picked. This, the
//! calls into a native build ([`super::native_calls`]) and the library's
//! loader (`crate::compile::back::native`) are the crate's only `unsafe`
//! code: calling a function built with `#[target_feature]` is unsafe,
//! and sound only where the processor has the feature, which `detect` checks.

use crate::compile::exec::interp::{Span, exec, finish, stage};
use crate::compile::exec::lane_code::Ins;
use crate::compile::exec::lanes::Reg;

/// The vector instructions the lane loops are compiled for, picked at run
/// time: the same source built three times, for AVX-512, AVX2 and the
/// baseline. None of them fuses a multiply and an add (Rust never contracts
/// floating-point expressions), so all three round exactly as the scalar
/// reference does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// The target's baseline (SSE2 on x86-64).
    Base,
    /// 256-bit vectors.
    Avx2,
    /// 512-bit vectors.
    Avx512,
}

#[cfg(target_arch = "x86_64")]
mod wide {
    use super::{Ins, Reg, Span, exec, finish, stage};

    /// `f` built for AVX-512 (`wide`) and for AVX2 (`narrow`): the same
    /// source, compiled with each feature enabled.
    macro_rules! built_for {
        ($($f:ident => $wide:ident, $narrow:ident ($($a:ident: $t:ty),*);)*) => {$(
            #[target_feature(enable = "avx512f")]
            pub fn $wide($($a: $t),*) {
                $f($($a),*);
            }
            #[target_feature(enable = "avx2")]
            pub fn $narrow($($a: $t),*) {
                $f($($a),*);
            }
        )*};
    }

    built_for! {
        exec => exec_512, exec_256(code: &[Ins], span: &[Span], r: &mut [Reg], nb: usize);
        stage => stage_512, stage_256(
            r: &mut [Reg], nb: usize, y: &[Reg], acc: &mut [Reg], slopes: &[u16], c: f64, first: bool
        );
        finish => finish_512, finish_256(
            r: &mut [Reg], nb: usize, y: &[Reg], acc: &[Reg], slopes: &[u16], c: f64
        );
    }
}

impl Isa {
    /// The widest this processor runs, or the one `RIGFIT_LANES_ISA`
    /// (`base`, `avx2`, `avx512`) names if the processor has it; decided once
    /// per process.
    pub fn detect() -> Self {
        static PICKED: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *PICKED.get_or_init(|| {
            let best = Self::widest();
            match std::env::var("RIGFIT_LANES_ISA").as_deref() {
                Ok("base") => Self::Base,
                Ok("avx2") if best != Self::Base => Self::Avx2,
                _ => best,
            }
        })
    }

    /// Every one this processor runs, narrowest first.
    pub fn available() -> Vec<Self> {
        let w = Self::widest();
        [Self::Base, Self::Avx2, Self::Avx512]
            .into_iter()
            .filter(|&i| i == Self::Base || i == Self::Avx2 && w != Self::Base || i == w)
            .collect()
    }

    /// The bytes of one vector register: the width the native lanes' C
    /// declares its vectors ([`crate::compile::back::c::source`]), so that
    /// each is one register and not two or four the compiler must split
    /// and spill.
    pub const fn vector_bytes(self) -> usize {
        match self {
            Self::Base => 16,
            Self::Avx2 => 32,
            Self::Avx512 => 64,
        }
    }

    /// What the C compiler is told beyond `-march=native` so that it uses
    /// no wider vectors than this (where [`Self::detect`] picked a narrower
    /// one than the processor's widest).
    pub fn narrowing_flags(self) -> &'static [&'static str] {
        if !cfg!(target_arch = "x86_64") {
            return &[];
        }
        match self {
            Self::Base => &["-mno-avx"],
            Self::Avx2 => &["-mno-avx512f"],
            Self::Avx512 => &[],
        }
    }

    fn widest() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                return Self::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Self::Avx2;
            }
        }
        Self::Base
    }

    #[expect(
        unsafe_code,
        reason = "calls the loops built for a feature `detect` found"
    )]
    pub(super) fn exec(self, code: &[Ins], span: &[Span], r: &mut [Reg], nb: usize) {
        match self {
            // SAFETY: `detect` returns these only where the processor has them.
            #[cfg(target_arch = "x86_64")]
            Self::Avx512 => unsafe { wide::exec_512(code, span, r, nb) },
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => unsafe { wide::exec_256(code, span, r, nb) },
            _ => exec(code, span, r, nb),
        }
    }

    #[expect(
        unsafe_code,
        reason = "calls the loops built for a feature `detect` found"
    )]
    #[expect(clippy::too_many_arguments, reason = "the loop's operands, as `stage`")]
    pub(super) fn stage(
        self,
        r: &mut [Reg],
        nb: usize,
        y: &[Reg],
        acc: &mut [Reg],
        slopes: &[u16],
        c: f64,
        first: bool,
    ) {
        match self {
            // SAFETY: as in `exec`.
            #[cfg(target_arch = "x86_64")]
            Self::Avx512 => unsafe { wide::stage_512(r, nb, y, acc, slopes, c, first) },
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => unsafe { wide::stage_256(r, nb, y, acc, slopes, c, first) },
            _ => stage(r, nb, y, acc, slopes, c, first),
        }
    }

    #[expect(
        unsafe_code,
        reason = "calls the loops built for a feature `detect` found"
    )]
    pub(super) fn finish(
        self,
        r: &mut [Reg],
        nb: usize,
        y: &[Reg],
        acc: &[Reg],
        slopes: &[u16],
        c: f64,
    ) {
        match self {
            // SAFETY: as in `exec`.
            #[cfg(target_arch = "x86_64")]
            Self::Avx512 => unsafe { wide::finish_512(r, nb, y, acc, slopes, c) },
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => unsafe { wide::finish_256(r, nb, y, acc, slopes, c) },
            _ => finish(r, nb, y, acc, slopes, c),
        }
    }
}
