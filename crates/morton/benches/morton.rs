//! Magic masks vs BMI2 `pdep`/`pext` vs the naive bit loop, for 3D encode
//! and decode over a prebuilt array of seeded random inputs. `pdep`/`pext`
//! are the run-time selected per-code methods (one non-inlined call each
//! unless built with `-C target-feature=+bmi2`); `*_slice` are the batch
//! methods, whose loop runs inside the BMI2-enabled function.
//!
//! Run with `cargo bench -p gridrt-morton`. Each iteration fills an output
//! array from the whole input array, so the numbers are throughput (the
//! compiler may vectorise what it can, as it would in a grid build).

use criterion::measurement::WallTime;
use criterion::{
    black_box, criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput,
};
use gridrt_morton::{bmi2::Bmi2, decode3, encode3, naive, MAX_COORD3};

const N: usize = 4096;

/// SplitMix64 (Steele, Lea & Flood 2014): seeded inputs without an RNG crate.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn coord3(&mut self) -> u32 {
        // The low 21 bits of a 64-bit draw: uniform in 0..=MAX_COORD3.
        (self.next_u64() & u64::from(MAX_COORD3)) as u32
    }
}

fn inputs() -> (Vec<(u32, u32, u32)>, Vec<u64>) {
    let mut rng = SplitMix64(0x6d6f_7274_6f6e);
    let cells = (0..N)
        .map(|_| (rng.coord3(), rng.coord3(), rng.coord3()))
        .collect();
    let codes = (0..N).map(|_| rng.next_u64() >> 1).collect();
    (cells, codes)
}

/// Times `f` over every cell, writing the codes to an output array.
fn bench_encode<F: Fn(u32, u32, u32) -> u64>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    cells: &[(u32, u32, u32)],
    f: F,
) {
    let mut out = vec![0u64; cells.len()];
    g.bench_function(name, |b| {
        b.iter(|| {
            for (o, &(x, y, z)) in out.iter_mut().zip(black_box(cells)) {
                *o = f(x, y, z);
            }
            black_box(&out);
        });
    });
}

/// Times `f` over every code, writing the cells to an output array.
fn bench_decode<F: Fn(u64) -> (u32, u32, u32)>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    codes: &[u64],
    f: F,
) {
    let mut out = vec![(0u32, 0u32, 0u32); codes.len()];
    g.bench_function(name, |b| {
        b.iter(|| {
            for (o, &code) in out.iter_mut().zip(black_box(codes)) {
                *o = f(code);
            }
            black_box(&out);
        });
    });
}

fn encode(c: &mut Criterion) {
    let (cells, _) = inputs();
    let mut g = c.benchmark_group("encode3");
    g.throughput(Throughput::Elements(N as u64));
    bench_encode(&mut g, "magic", &cells, encode3);
    match Bmi2::detect() {
        Some(cpu) => {
            bench_encode(&mut g, "pdep", &cells, |x, y, z| cpu.encode3(x, y, z));
            let mut out = vec![0u64; N];
            g.bench_function("pdep_slice", |b| {
                b.iter(|| {
                    cpu.encode3_slice(black_box(&cells), &mut out);
                    black_box(&out);
                });
            });
        }
        None => eprintln!("encode3/pdep: BMI2 not available on this CPU, skipped"),
    }
    bench_encode(&mut g, "naive", &cells, naive::encode3);
    g.finish();
}

fn decode(c: &mut Criterion) {
    let (_, codes) = inputs();
    let mut g = c.benchmark_group("decode3");
    g.throughput(Throughput::Elements(N as u64));
    bench_decode(&mut g, "magic", &codes, decode3);
    match Bmi2::detect() {
        Some(cpu) => {
            bench_decode(&mut g, "pext", &codes, |code| cpu.decode3(code));
            let mut out = vec![(0u32, 0u32, 0u32); N];
            g.bench_function("pext_slice", |b| {
                b.iter(|| {
                    cpu.decode3_slice(black_box(&codes), &mut out);
                    black_box(&out);
                });
            });
        }
        None => eprintln!("decode3/pext: BMI2 not available on this CPU, skipped"),
    }
    bench_decode(&mut g, "naive", &codes, naive::decode3);
    g.finish();
}

criterion_group!(benches, encode, decode);
criterion_main!(benches);
