//! Morton codes by the x86-64 BMI2 instructions `pdep` (parallel bit
//! deposit) and `pext` (parallel bit extract): one instruction per axis.
//!
//! Use it through a [`Bmi2`] token, which only [`Bmi2::detect`] can make and
//! only when the CPU has BMI2, so every method is safe to call:
//!
//! ```
//! use gridrt_morton::{bmi2::Bmi2, encode3};
//! let code = match Bmi2::detect() {
//!     Some(cpu) => cpu.encode3(5, 2, 1),
//!     None => encode3(5, 2, 1), // the portable default
//! };
//! assert_eq!(code, 85);
//! ```
//!
//! # How the path is chosen
//! - Built with the `bmi2` target feature (`-C target-cpu=native` on a
//!   recent CPU, or `-C target-feature=+bmi2`): [`Bmi2::detect`] is a
//!   constant `Some`, and the methods inline into the caller.
//! - Otherwise, on x86-64: [`Bmi2::detect`] asks the CPU at run time with
//!   `is_x86_feature_detected!("bmi2")`. The standard library caches the
//!   CPUID answer in a static atomic after the first query, so `detect` is
//!   cheap; still, get the token once, outside the hot loop. The methods
//!   then call a `#[target_feature(enable = "bmi2")]` function, which the
//!   compiler cannot inline into code built without the feature: one call
//!   per code. For bulk work use [`Bmi2::encode3_slice`] and
//!   [`Bmi2::decode3_slice`], whose loops run inside such a function.
//! - On any other architecture [`Bmi2::detect`] is always `None`.
//!
//! # Why it is not the default
//! The crate-level functions use magic masks everywhere. `pdep`/`pext` are
//! fast (3 cycles) on Intel since Haswell and on AMD since Zen 3, but
//! microcoded and far slower than the masks on AMD Zen 1 and Zen 2, which
//! do report BMI2. Pick this path after measuring (`cargo bench -p
//! gridrt-morton`).
//!
//! All four functions agree bit for bit with the portable ones, including
//! the out-of-range rule: [`Bmi2::encode3`] keeps the low 21 bits of each
//! coordinate (the deposit masks have 21 bits) and [`Bmi2::decode3`]
//! ignores bit 63.

/// Proof that the running CPU supports BMI2. Only [`Bmi2::detect`] makes
/// one, so holding it makes the `pdep`/`pext` methods safe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bmi2 {
    _private: (),
}

impl Bmi2 {
    /// The token if this CPU has BMI2, `None` otherwise (always `None` off
    /// x86-64). See the [module docs](self) for how this is decided.
    #[inline]
    #[must_use]
    pub fn detect() -> Option<Self> {
        if is_available() {
            Some(Self { _private: () })
        } else {
            None
        }
    }

    /// [`crate::encode3`] by `pdep`.
    #[inline]
    #[must_use]
    pub fn encode3(self, x: u32, y: u32, z: u32) -> u64 {
        // SAFETY: `self` exists only if `detect` found BMI2 on this CPU.
        #[cfg(target_arch = "x86_64")]
        return unsafe { imp::encode3(x, y, z) };
        #[cfg(not(target_arch = "x86_64"))]
        return crate::encode3(x, y, z);
    }

    /// [`crate::decode3`] by `pext`.
    #[inline]
    #[must_use]
    pub fn decode3(self, code: u64) -> (u32, u32, u32) {
        // SAFETY: `self` exists only if `detect` found BMI2 on this CPU.
        #[cfg(target_arch = "x86_64")]
        return unsafe { imp::decode3(code) };
        #[cfg(not(target_arch = "x86_64"))]
        return crate::decode3(code);
    }

    /// [`Bmi2::encode3`] over a slice: `out[i] = encode3(cells[i])`.
    ///
    /// Prefer this in bulk work when the build does not enable BMI2 at
    /// compile time: the whole loop then runs inside one BMI2-enabled
    /// function, with `pdep` inlined, instead of one call per code.
    ///
    /// # Panics
    /// If `cells` and `out` differ in length.
    ///
    /// ```
    /// if let Some(cpu) = gridrt_morton::bmi2::Bmi2::detect() {
    ///     let mut out = [0; 2];
    ///     cpu.encode3_slice(&[(5, 2, 1), (1, 0, 0)], &mut out);
    ///     assert_eq!(out, [85, 1]);
    /// }
    /// ```
    #[inline]
    pub fn encode3_slice(self, cells: &[(u32, u32, u32)], out: &mut [u64]) {
        assert_eq!(
            cells.len(),
            out.len(),
            "encode3_slice: input and output lengths differ"
        );
        // SAFETY: `self` exists only if `detect` found BMI2 on this CPU.
        #[cfg(target_arch = "x86_64")]
        unsafe {
            imp::encode3_slice(cells, out);
        }
        #[cfg(not(target_arch = "x86_64"))]
        for (o, &(x, y, z)) in out.iter_mut().zip(cells) {
            *o = crate::encode3(x, y, z);
        }
    }

    /// [`Bmi2::decode3`] over a slice: `out[i] = decode3(codes[i])`. See
    /// [`Bmi2::encode3_slice`] for when to prefer it.
    ///
    /// # Panics
    /// If `codes` and `out` differ in length.
    ///
    /// ```
    /// if let Some(cpu) = gridrt_morton::bmi2::Bmi2::detect() {
    ///     let mut out = [(0, 0, 0); 2];
    ///     cpu.decode3_slice(&[85, 4], &mut out);
    ///     assert_eq!(out, [(5, 2, 1), (0, 0, 1)]);
    /// }
    /// ```
    #[inline]
    pub fn decode3_slice(self, codes: &[u64], out: &mut [(u32, u32, u32)]) {
        assert_eq!(
            codes.len(),
            out.len(),
            "decode3_slice: input and output lengths differ"
        );
        // SAFETY: `self` exists only if `detect` found BMI2 on this CPU.
        #[cfg(target_arch = "x86_64")]
        unsafe {
            imp::decode3_slice(codes, out);
        }
        #[cfg(not(target_arch = "x86_64"))]
        for (o, &code) in out.iter_mut().zip(codes) {
            *o = crate::decode3(code);
        }
    }

    /// [`crate::encode2`] by `pdep`.
    #[inline]
    #[must_use]
    pub fn encode2(self, x: u32, y: u32) -> u64 {
        // SAFETY: `self` exists only if `detect` found BMI2 on this CPU.
        #[cfg(target_arch = "x86_64")]
        return unsafe { imp::encode2(x, y) };
        #[cfg(not(target_arch = "x86_64"))]
        return crate::encode2(x, y);
    }

    /// [`crate::decode2`] by `pext`.
    #[inline]
    #[must_use]
    pub fn decode2(self, code: u64) -> (u32, u32) {
        // SAFETY: `self` exists only if `detect` found BMI2 on this CPU.
        #[cfg(target_arch = "x86_64")]
        return unsafe { imp::decode2(code) };
        #[cfg(not(target_arch = "x86_64"))]
        return crate::decode2(code);
    }
}

/// True when this CPU has BMI2, so that [`Bmi2::detect`] returns a token.
///
/// ```
/// assert_eq!(gridrt_morton::bmi2::is_available(), gridrt_morton::bmi2::Bmi2::detect().is_some());
/// ```
#[inline]
#[must_use]
pub fn is_available() -> bool {
    #[cfg(all(target_arch = "x86_64", target_feature = "bmi2"))]
    return true;
    #[cfg(all(target_arch = "x86_64", not(target_feature = "bmi2")))]
    return std::is_x86_feature_detected!("bmi2");
    #[cfg(not(target_arch = "x86_64"))]
    return false;
}

#[cfg(target_arch = "x86_64")]
mod imp {
    //! The BMI2 bodies. Each is `unsafe` because it must run only on a CPU
    //! with BMI2; callers hold a [`super::Bmi2`] token as proof.
    //!
    //! The intrinsics are `unsafe fn`s on older compilers and safe inside a
    //! `#[target_feature]` function on newer ones, hence the
    //! `allow(unused_unsafe)`.

    use crate::{X2_MASK, X3_MASK};
    use core::arch::x86_64::{_pdep_u64, _pext_u64};

    /// # Safety
    /// The CPU must support BMI2.
    #[target_feature(enable = "bmi2")]
    pub(super) unsafe fn encode3(x: u32, y: u32, z: u32) -> u64 {
        // SAFETY: the caller guarantees BMI2.
        #[allow(unused_unsafe)]
        unsafe {
            _pdep_u64(u64::from(x), X3_MASK)
                | _pdep_u64(u64::from(y), X3_MASK << 1)
                | _pdep_u64(u64::from(z), X3_MASK << 2)
        }
    }

    /// # Safety
    /// The CPU must support BMI2.
    #[target_feature(enable = "bmi2")]
    pub(super) unsafe fn decode3(code: u64) -> (u32, u32, u32) {
        // SAFETY: the caller guarantees BMI2. Each extract has 21 mask bits,
        // so the casts are lossless.
        #[allow(unused_unsafe)]
        unsafe {
            (
                _pext_u64(code, X3_MASK) as u32,
                _pext_u64(code, X3_MASK << 1) as u32,
                _pext_u64(code, X3_MASK << 2) as u32,
            )
        }
    }

    /// # Safety
    /// The CPU must support BMI2.
    #[target_feature(enable = "bmi2")]
    pub(super) unsafe fn encode3_slice(cells: &[(u32, u32, u32)], out: &mut [u64]) {
        for (o, &(x, y, z)) in out.iter_mut().zip(cells) {
            // SAFETY: the caller guarantees BMI2.
            *o = unsafe { encode3(x, y, z) };
        }
    }

    /// # Safety
    /// The CPU must support BMI2.
    #[target_feature(enable = "bmi2")]
    pub(super) unsafe fn decode3_slice(codes: &[u64], out: &mut [(u32, u32, u32)]) {
        for (o, &code) in out.iter_mut().zip(codes) {
            // SAFETY: the caller guarantees BMI2.
            *o = unsafe { decode3(code) };
        }
    }

    /// # Safety
    /// The CPU must support BMI2.
    #[target_feature(enable = "bmi2")]
    pub(super) unsafe fn encode2(x: u32, y: u32) -> u64 {
        // SAFETY: the caller guarantees BMI2.
        #[allow(unused_unsafe)]
        unsafe {
            _pdep_u64(u64::from(x), X2_MASK) | _pdep_u64(u64::from(y), X2_MASK << 1)
        }
    }

    /// # Safety
    /// The CPU must support BMI2.
    #[target_feature(enable = "bmi2")]
    pub(super) unsafe fn decode2(code: u64) -> (u32, u32) {
        // SAFETY: the caller guarantees BMI2. Each extract has 32 mask bits,
        // so the casts are lossless.
        #[allow(unused_unsafe)]
        unsafe {
            (
                _pext_u64(code, X2_MASK) as u32,
                _pext_u64(code, X2_MASK << 1) as u32,
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detect_agrees_with_is_available() {
        assert_eq!(Bmi2::detect().is_some(), is_available());
    }

    #[test]
    fn lecture_example_when_available() {
        let Some(cpu) = Bmi2::detect() else {
            eprintln!("BMI2 not available on this CPU: skipped");
            return;
        };
        assert_eq!(cpu.encode3(5, 2, 1), 85);
        assert_eq!(cpu.decode3(85), (5, 2, 1));
        assert_eq!(cpu.encode2(3, 5), 0b100111);
        assert_eq!(cpu.decode2(0b100111), (3, 5));
        // Out-of-range rule: the same as the portable functions.
        assert_eq!(
            cpu.encode3(u32::MAX, 1 << 21, 7),
            crate::encode3(u32::MAX, 1 << 21, 7)
        );
        assert_eq!(cpu.decode3(u64::MAX), crate::decode3(u64::MAX));
    }

    #[test]
    fn slices_match_single_calls() {
        let Some(cpu) = Bmi2::detect() else {
            return;
        };
        let cells: Vec<_> = (0..100u32).map(|i| (i * 7919, i, u32::MAX - i)).collect();
        let mut codes = vec![0; cells.len()];
        cpu.encode3_slice(&cells, &mut codes);
        for (&(x, y, z), &c) in cells.iter().zip(&codes) {
            assert_eq!(c, crate::encode3(x, y, z));
        }
        let mut back = vec![(0, 0, 0); codes.len()];
        cpu.decode3_slice(&codes, &mut back);
        for (&c, &cell) in codes.iter().zip(&back) {
            assert_eq!(cell, crate::decode3(c));
        }
    }

    #[test]
    #[should_panic(expected = "lengths differ")]
    fn slice_length_mismatch_panics() {
        match Bmi2::detect() {
            Some(cpu) => cpu.encode3_slice(&[(1, 2, 3)], &mut []),
            None => panic!("lengths differ (BMI2 not available; nothing to test)"),
        }
    }
}
