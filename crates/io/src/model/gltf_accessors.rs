//! Bounds-checked reading of glTF accessors: every element range is checked
//! against its buffer view and buffer before a byte is read, so a truncated
//! or inconsistent file is an error, never a panic.

use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use std::borrow::Cow;

/// Bytes per component of a data type.
fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// The byte range of an accessor's elements in a buffer view, checked:
/// `(buffer data, start, stride)`.
pub(super) fn element_slice<'b>(
    view: &gltf::buffer::View,
    offset: usize,
    count: usize,
    elem: usize,
    buffers: &'b [Cow<'_, [u8]>],
) -> std::result::Result<(&'b [u8], usize), String> {
    let data = buffers
        .get(view.buffer().index())
        .ok_or_else(|| format!("buffer view {} has no buffer", view.index()))?;
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "buffer view {} has stride {stride}, less than the element size {elem}",
            view.index()
        ));
    }
    let view_end = view
        .offset()
        .checked_add(view.length())
        .filter(|&e| e <= data.len())
        .ok_or_else(|| {
            format!(
                "buffer view {} runs past the end of its buffer",
                view.index()
            )
        })?;
    if count == 0 {
        return Ok((&[], stride));
    }
    let start = view.offset().checked_add(offset);
    let end = start
        .and_then(|s| stride.checked_mul(count - 1).and_then(|x| x.checked_add(s)))
        .and_then(|x| x.checked_add(elem));
    match (start, end) {
        (Some(s), Some(e)) if e <= view_end => Ok((&data[s..e], stride)),
        _ => Err(format!(
            "{count} elements at offset {offset} do not fit in buffer view {} ({} bytes)",
            view.index(),
            view.length()
        )),
    }
}

/// Reads `count` elements of `elem` bytes each with a stride, decoding each.
fn read_elements<T>(
    bytes: &[u8],
    stride: usize,
    count: usize,
    elem: usize,
    decode: impl Fn(&[u8]) -> T,
) -> Vec<T> {
    (0..count)
        .map(|i| decode(&bytes[i * stride..i * stride + elem]))
        .collect()
}

fn f32_le(b: &[u8]) -> f32 {
    f32::from_le_bytes([b[0], b[1], b[2], b[3]])
}

/// Reads a FLOAT VEC3 accessor (positions, normals), sparse or not.
pub(super) fn read_vec3(
    acc: &gltf::Accessor,
    buffers: &[Cow<[u8]>],
) -> std::result::Result<Vec<[f32; 3]>, String> {
    if acc.data_type() != DataType::F32 || acc.dimensions() != Dimensions::Vec3 {
        return Err(format!(
            "accessor {} is {:?} {:?}; expected FLOAT VEC3 (quantized meshes are not supported)",
            acc.index(),
            acc.data_type(),
            acc.dimensions()
        ));
    }
    let count = acc.count();
    let decode = |b: &[u8]| [f32_le(b), f32_le(&b[4..]), f32_le(&b[8..])];
    let mut out = match acc.view() {
        Some(view) => {
            let (bytes, stride) = element_slice(&view, acc.offset(), count, 12, buffers)?;
            read_elements(bytes, stride, count, 12, decode)
        }
        None => {
            if count > 1 << 24 {
                return Err(format!(
                    "accessor {} has an absurd count {count}",
                    acc.index()
                ));
            }
            vec![[0.0; 3]; count]
        }
    };
    if let Some(sparse) = acc.sparse() {
        let n = sparse.count();
        let iv = sparse.indices();
        let isize_ = match iv.index_type() {
            gltf::accessor::sparse::IndexType::U8 => 1,
            gltf::accessor::sparse::IndexType::U16 => 2,
            gltf::accessor::sparse::IndexType::U32 => 4,
        };
        let (ib, istride) = element_slice(&iv.view(), iv.offset(), n, isize_, buffers)?;
        let idx = read_elements(ib, istride, n, isize_, read_uint);
        let vv = sparse.values();
        let (vb, vstride) = element_slice(&vv.view(), vv.offset(), n, 12, buffers)?;
        let vals = read_elements(vb, vstride, n, 12, decode);
        for (i, v) in idx.into_iter().zip(vals) {
            let slot = out
                .get_mut(i as usize)
                .ok_or_else(|| format!("sparse index {i} is out of range ({count} elements)"))?;
            *slot = v;
        }
    }
    Ok(out)
}

/// A little-endian unsigned integer of 1, 2 or 4 bytes.
fn read_uint(b: &[u8]) -> u32 {
    match b.len() {
        1 => u32::from(b[0]),
        2 => u32::from(u16::from_le_bytes([b[0], b[1]])),
        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}

/// Reads an index accessor (UNSIGNED_BYTE/SHORT/INT SCALAR) as the
/// triangles of a primitive in `mode`. A list of triangles goes straight
/// into its triples, with no index array beside them (on a large mesh that
/// array would be as large as the triangles).
pub(super) fn read_triangles(
    acc: &gltf::Accessor,
    mode: Mode,
    buffers: &[Cow<[u8]>],
) -> std::result::Result<Vec<[u32; 3]>, String> {
    let size = component_size(acc.data_type());
    let unsigned = matches!(
        acc.data_type(),
        DataType::U8 | DataType::U16 | DataType::U32
    );
    if !unsigned || acc.dimensions() != Dimensions::Scalar || acc.sparse().is_some() {
        return Err(format!(
            "accessor {} is {:?} {:?}{}; indices must be an unsigned SCALAR accessor",
            acc.index(),
            acc.data_type(),
            acc.dimensions(),
            if acc.sparse().is_some() {
                " (sparse)"
            } else {
                ""
            }
        ));
    }
    let view = acc
        .view()
        .ok_or_else(|| format!("index accessor {} has no buffer view", acc.index()))?;
    let (bytes, stride) = element_slice(&view, acc.offset(), acc.count(), size, buffers)?;
    if matches!(mode, Mode::TriangleStrip | Mode::TriangleFan) {
        let idx = read_elements(bytes, stride, acc.count(), size, read_uint);
        return Ok(assemble(&idx, mode));
    }
    let at = |i: usize| read_uint(&bytes[i * stride..i * stride + size]);
    Ok((0..acc.count() / 3)
        .map(|t| [at(3 * t), at(3 * t + 1), at(3 * t + 2)])
        .collect())
}

/// Triangles from an index list in the primitive's mode.
pub(super) fn assemble(idx: &[u32], mode: Mode) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (2..idx.len())
            .map(|i| {
                // Every other triangle is flipped to keep the winding.
                if i % 2 == 0 {
                    [idx[i - 2], idx[i - 1], idx[i]]
                } else {
                    [idx[i - 1], idx[i - 2], idx[i]]
                }
            })
            .collect(),
        Mode::TriangleFan => (2..idx.len())
            .map(|i| [idx[0], idx[i - 1], idx[i]])
            .collect(),
        _ => idx.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    }
}
