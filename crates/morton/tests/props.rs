use gridrt_morton::{bmi2::Bmi2, decode2, decode3, encode2, encode3, naive, MAX_COORD3};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// Deterministic runs: a fixed seed, and no regression files written.
fn config() -> Config {
    Config {
        cases: 4096,
        rng_seed: RngSeed::Fixed(0x6d6f_7274_6f6e), // "morton"
        failure_persistence: None,
        ..Config::default()
    }
}

/// A 21-bit coordinate, biased towards the ends of the range where carries
/// and masks go wrong.
fn coord3() -> impl Strategy<Value = u32> {
    prop_oneof![
        4 => 0..=MAX_COORD3,
        1 => prop::sample::select(vec![0, 1, 2, MAX_COORD3 - 1, MAX_COORD3, 1 << 20, (1 << 20) - 1]),
    ]
}

fn coord2() -> impl Strategy<Value = u32> {
    prop_oneof![
        4 => any::<u32>(),
        1 => prop::sample::select(vec![0, 1, u32::MAX - 1, u32::MAX, 1 << 31, (1 << 31) - 1]),
    ]
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn decode3_undoes_encode3_over_21_bits(x in coord3(), y in coord3(), z in coord3()) {
        let c = encode3(x, y, z);
        prop_assert_eq!(c >> 63, 0);
        prop_assert_eq!(decode3(c), (x, y, z));
    }

    #[test]
    fn encode3_undoes_decode3_below_bit_63(c in any::<u64>()) {
        let (x, y, z) = decode3(c);
        prop_assert!(x <= MAX_COORD3 && y <= MAX_COORD3 && z <= MAX_COORD3);
        prop_assert_eq!(encode3(x, y, z), c & (u64::MAX >> 1));
    }

    #[test]
    fn decode2_undoes_encode2_over_32_bits(x in coord2(), y in coord2()) {
        prop_assert_eq!(decode2(encode2(x, y)), (x, y));
    }

    #[test]
    fn encode2_undoes_decode2(c in any::<u64>()) {
        let (x, y) = decode2(c);
        prop_assert_eq!(encode2(x, y), c);
    }

    #[test]
    fn masks_agree_with_naive(x in any::<u32>(), y in any::<u32>(), z in any::<u32>(), c in any::<u64>()) {
        // Full u32 inputs: the out-of-range rule must agree too.
        prop_assert_eq!(encode3(x, y, z), naive::encode3(x, y, z));
        prop_assert_eq!(decode3(c), naive::decode3(c));
        prop_assert_eq!(encode2(x, y), naive::encode2(x, y));
        prop_assert_eq!(decode2(c), naive::decode2(c));
    }

    #[test]
    fn bmi2_agrees_with_masks(x in any::<u32>(), y in any::<u32>(), z in any::<u32>(), c in any::<u64>()) {
        if let Some(cpu) = Bmi2::detect() {
            prop_assert_eq!(cpu.encode3(x, y, z), encode3(x, y, z));
            prop_assert_eq!(cpu.decode3(c), decode3(c));
            prop_assert_eq!(cpu.encode2(x, y), encode2(x, y));
            prop_assert_eq!(cpu.decode2(c), decode2(c));
        }
    }

    #[test]
    fn encode3_keeps_the_low_21_bits(x in any::<u32>(), y in any::<u32>(), z in any::<u32>()) {
        let m = MAX_COORD3;
        prop_assert_eq!(encode3(x, y, z), encode3(x & m, y & m, z & m));
        prop_assert_eq!(decode3(encode3(x, y, z)), (x & m, y & m, z & m));
    }

    #[test]
    fn encode3_is_increasing_along_each_axis(
        a in coord3(), b in coord3(), y in coord3(), z in coord3(),
    ) {
        // With the other two fixed, a larger coordinate gives a larger code.
        let (lo, hi) = (a.min(b), a.max(b));
        prop_assert_eq!(encode3(lo, y, z) < encode3(hi, y, z), lo < hi);
        prop_assert_eq!(encode3(y, lo, z) < encode3(y, hi, z), lo < hi);
        prop_assert_eq!(encode3(y, z, lo) < encode3(y, z, hi), lo < hi);
    }

    #[test]
    fn encode3_is_monotone_in_the_product_order(
        p in (coord3(), coord3(), coord3()), q in (coord3(), coord3(), coord3()),
    ) {
        // If p <= q on every axis then code(p) <= code(q): the Z-curve never
        // goes back past a cell that dominates it.
        let lo = (p.0.min(q.0), p.1.min(q.1), p.2.min(q.2));
        let hi = (p.0.max(q.0), p.1.max(q.1), p.2.max(q.2));
        prop_assert!(encode3(lo.0, lo.1, lo.2) <= encode3(hi.0, hi.1, hi.2));
    }

    #[test]
    fn encode2_is_increasing_along_each_axis(a in coord2(), b in coord2(), o in coord2()) {
        let (lo, hi) = (a.min(b), a.max(b));
        prop_assert_eq!(encode2(lo, o) < encode2(hi, o), lo < hi);
        prop_assert_eq!(encode2(o, lo) < encode2(o, hi), lo < hi);
    }
}

#[test]
fn aligned_blocks_are_contiguous_ranges() {
    // The point of a Z-order key for a grid: every aligned 2^k-cube of cells
    // occupies one contiguous run of 8^k codes.
    for k in 0..4u32 {
        let side = 1u32 << k;
        for (bx, by, bz) in [(0, 0, 0), (1, 0, 0), (3, 5, 2), (7, 7, 7)] {
            let (ox, oy, oz) = (bx * side, by * side, bz * side);
            let base = encode3(ox, oy, oz);
            let mut codes: Vec<u64> = (0..side)
                .flat_map(|i| (0..side).flat_map(move |j| (0..side).map(move |l| (i, j, l))))
                .map(|(i, j, l)| encode3(ox + i, oy + j, oz + l))
                .collect();
            codes.sort_unstable();
            let expected: Vec<u64> = (base..base + u64::from(side).pow(3)).collect();
            assert_eq!(codes, expected, "block {k} at ({ox}, {oy}, {oz})");
        }
    }
}

#[test]
fn all_small_cells_agree_with_naive_and_bmi2() {
    let cpu = Bmi2::detect();
    for x in 0..32 {
        for y in 0..32 {
            for z in 0..32 {
                let c = encode3(x, y, z);
                assert_eq!(c, naive::encode3(x, y, z));
                assert_eq!(decode3(c), (x, y, z));
                if let Some(cpu) = cpu {
                    assert_eq!(cpu.encode3(x, y, z), c);
                    assert_eq!(cpu.decode3(c), (x, y, z));
                }
            }
            assert_eq!(encode2(x, y), naive::encode2(x, y));
        }
    }
}
