//! Scene transforms (`translate`, `scale`, `rotate`, `euler`, `matrix`) as matrices.

use crate::scene::unit;
use crate::schema::TransformDesc;
use glam::{DMat4, DQuat, DVec3};

/// One transform step as a matrix.
pub(crate) fn transform_matrix(op: &TransformDesc) -> DMat4 {
    match op {
        TransformDesc::Translate(t) => DMat4::from_translation(DVec3::from_array(t.0)),
        TransformDesc::Scale(s) => DMat4::from_scale(DVec3::from_array(s.0)),
        TransformDesc::Rotate { axis, degrees } => {
            DMat4::from_axis_angle(unit(axis.0), degrees.0.to_radians())
        }
        TransformDesc::Euler { x, y, z } => DMat4::from_quat(DQuat::from_euler(
            glam::EulerRot::ZYX,
            z.0.to_radians(),
            y.0.to_radians(),
            x.0.to_radians(),
        )),
        TransformDesc::Matrix(m) => {
            // Rows in the file; glam wants columns.
            DMat4::from_cols_array_2d(&m.0).transpose()
        }
    }
}
