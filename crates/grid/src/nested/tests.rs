//! Unit tests of the nested grids' planning.

use super::layout;
use crate::geom::Geom;
use gridrt_bbox::{Aabb, Real, Vec3};

/// A plan is refused before its cells are counted when its references
/// and offsets alone would take more than the budget left: the same
/// layout is made with room for them and refused with four bytes less.
#[test]
fn a_layout_needs_room_for_its_references_and_offsets() {
    let geom = Geom::new(Aabb::new(Vec3::ZERO, Vec3::splat(4.0)), [4, 4, 4]);
    // Boxes in one cell each, and one across a 2 × 2 × 1 block of cells.
    let mut boxes: Vec<Aabb> = (0..16)
        .map(|i| {
            let lo = Vec3::new((i % 4) as Real, (i / 4) as Real, 0.0) + Vec3::splat(0.25);
            Aabb::new(lo, lo + Vec3::splat(0.5))
        })
        .collect();
    boxes.push(Aabb::new(Vec3::splat(0.5), Vec3::new(1.5, 1.5, 0.75)));
    let inner: Vec<u32> = (0..boxes.len() as u32).collect();
    let total = 16 + 4;
    let need = 4 * (total + geom.cell_count() as usize + 1);
    let (offsets, _) = layout(&geom, &inner, &boxes, inner.len(), need, |_| true)
        .expect("a layout with room for it");
    assert_eq!(offsets.last().copied(), Some(total as u32));
    assert!(layout(&geom, &inner, &boxes, inner.len(), need - 4, |_| true).is_none());
}
