//! Shared test support: primitives, scenes, and the grid-versus-exhaustive
//! comparison every test uses.

#![allow(dead_code)]

pub mod prims;
pub mod scenes;

use gridrt_grid::{
    Accelerator, CellStorage, Exhaustive, Grid, GridConfig, Hit, Primitive, Ray, Real,
};

/// Every combination of storage, mailbox and insertion mode; half of them
/// nest a grid in every cell of two references or more.
pub fn all_configs() -> Vec<GridConfig> {
    let mut v = Vec::new();
    for storage in [CellStorage::Hashed, CellStorage::Dense] {
        for mailbox in [false, true] {
            for exact_insertion in [false, true] {
                v.push(GridConfig {
                    storage,
                    mailbox,
                    exact_insertion,
                    nest_min_refs: if mailbox == exact_insertion { 2 } else { 0 },
                    ..GridConfig::default()
                });
            }
        }
    }
    v
}

/// The exhaustive answer and the grid's for one query, for every config;
/// panics with a description on the first difference. Hits must agree in
/// primitive and bitwise in `t`, `u`, `v`.
pub struct Checker<P: Primitive + Clone> {
    pub exhaustive: Exhaustive<P>,
    pub grids: Vec<Grid<P>>,
}

impl<P: Primitive<Shared = ()> + Clone + std::fmt::Debug> Checker<P> {
    /// Builds the reference and one grid per config (checking each grid's
    /// invariants).
    pub fn new(prims: Vec<P>, configs: &[GridConfig]) -> Self
    where
        P: Send,
    {
        let grids: Vec<_> = configs
            .iter()
            .map(|c| Grid::build(prims.clone(), c))
            .inspect(|g| {
                if let Err(e) = g.check_invariants() {
                    panic!("invariants broken for {:?}: {e}", g.config());
                }
            })
            .collect();
        Self {
            exhaustive: Exhaustive::new(prims),
            grids,
        }
    }

    /// One grid per config of [`all_configs`].
    pub fn all(prims: Vec<P>) -> Self
    where
        P: Send,
    {
        Self::new(prims, &all_configs())
    }

    /// Compares closest and any hit for one ray and range; returns the reference hit.
    pub fn check(&self, ray: &Ray, t_min: Real, t_max: Real) -> Option<Hit> {
        let want = self.exhaustive.closest_hit(ray, t_min, t_max, &mut ());
        let want_any = self.exhaustive.any_hit(ray, t_min, t_max, &mut ());
        for g in &self.grids {
            let mut s = g.scratch();
            // Twice with the same scratch: the mailbox must not carry over.
            for _ in 0..2 {
                let got = g.closest_hit(ray, t_min, t_max, &mut s);
                assert!(
                    same(&got, &want),
                    "closest_hit differs for {:?}\n ray {ray:?} [{t_min}, {t_max}]\n grid {got:?}\n want {want:?}\n dims {:?}",
                    g.config(),
                    g.stats().dims
                );
                if let Some(h) = got {
                    // The slot holds the primitive hit.
                    assert_eq!(g.primitive_of(h.slot), h.prim);
                }
                let got_any = g.any_hit(ray, t_min, t_max, &mut s);
                assert_eq!(
                    got_any,
                    want_any,
                    "any_hit differs for {:?}\n ray {ray:?} [{t_min}, {t_max}]",
                    g.config()
                );
            }
        }
        want
    }
}

/// Equal hits: same primitive, bitwise-equal t, u, v.
pub fn same(a: &Option<Hit>, b: &Option<Hit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.prim == b.prim
                && a.t.to_bits() == b.t.to_bits()
                && a.u.to_bits() == b.u.to_bits()
                && a.v.to_bits() == b.v.to_bits()
        }
        _ => false,
    }
}
