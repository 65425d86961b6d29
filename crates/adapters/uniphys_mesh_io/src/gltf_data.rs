//! glTF binary data: buffers (GLB chunk, data URIs, external files) and bounds-checked accessor
//! reads. Every accessor is checked against its buffer view and buffer before a single element
//! is read, so corrupt counts cannot cause long loops or large allocations.

use std::path::Path;

use ::gltf::Accessor;
use ::gltf::accessor::{DataType, Dimensions};

use crate::paths::{resolve_absolute, resolve_reference};
use crate::source::Session;
use crate::{IngestError, IngestResult};

/// Checks the 12-byte GLB header and the first chunk header against the file size.
pub(crate) fn check_glb_header(path: &Path, bytes: &[u8]) -> IngestResult<()> {
    let err = |m: String| IngestError::parse(path, "glb", m);
    let word = |at: usize| {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    };
    let (Some(version), Some(length), Some(chunk)) = (word(4), word(8), word(12)) else {
        return Err(err(format!(
            "only {} bytes, shorter than the GLB header and first chunk header",
            bytes.len()
        )));
    };
    if version != 2 {
        return Err(err(format!("GLB version {version}, expected 2")));
    }
    if length < 20 || length > bytes.len() {
        return Err(err(format!(
            "the header declares {length} bytes but the file has {} bytes; the file is truncated",
            bytes.len()
        )));
    }
    if chunk.saturating_add(20) > length {
        return Err(err(format!(
            "the JSON chunk declares {chunk} bytes, more than the {length}-byte file holds"
        )));
    }
    Ok(())
}

/// Loads every buffer of the document, in order: the GLB binary chunk, data URIs, or files next
/// to `path` (read through the session so they are size-limited and hashed).
pub(crate) fn load_buffers(
    document: &::gltf::Document,
    mut blob: Option<Vec<u8>>,
    path: &Path,
    format: &'static str,
    session: &mut Session<'_>,
) -> IngestResult<Vec<Vec<u8>>> {
    let mut out = Vec::new();
    for buffer in document.buffers() {
        let i = buffer.index();
        let data = match buffer.source() {
            ::gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                IngestError::parse(
                    path,
                    format,
                    format!("buffer {i} refers to the GLB binary chunk, but there is none"),
                )
            })?,
            ::gltf::buffer::Source::Uri(uri) => load_uri(path, uri, format, session)?,
        };
        if data.len() < buffer.length() {
            return Err(IngestError::parse(
                path,
                format,
                format!(
                    "buffer {i} declares {} bytes but only {} are present",
                    buffer.length(),
                    data.len()
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// The bytes behind a glTF `uri`: a base64 data URI, or a file inside the asset's directory.
pub(crate) fn load_uri(
    path: &Path,
    uri: &str,
    format: &'static str,
    session: &mut Session<'_>,
) -> IngestResult<Vec<u8>> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((meta, data)) = rest.split_once(',') else {
            return Err(IngestError::parse(
                path,
                format,
                "a data URI has no ',' separator",
            ));
        };
        if !meta.ends_with(";base64") {
            return Err(IngestError::Unsupported {
                path: path.to_path_buf(),
                what: "a data URI that is not base64-encoded".to_owned(),
            });
        }
        return base64::decode(data.trim()).map_err(|e| {
            IngestError::parse(path, format, format!("bad base64 in a data URI: {e}"))
        });
    }
    let file = if let Some(absolute) = uri.strip_prefix("file://") {
        resolve_absolute(path, &session.root, uri, absolute)?
    } else if uri.starts_with("http://") || uri.starts_with("https://") {
        return Err(IngestError::Unsupported {
            path: path.to_path_buf(),
            what: format!("the remote URI {uri:?} (download the file and reference it relatively)"),
        });
    } else {
        let decoded = urlencoding::decode(uri).map_err(|e| {
            IngestError::parse(
                path,
                format,
                format!("bad percent-encoding in URI {uri:?}: {e}"),
            )
        })?;
        let dir = path.parent().unwrap_or(Path::new("/"));
        resolve_reference(path, dir, &session.root, &decoded)?
    };
    session.read(&file)
}

/// An accessor's bytes after the bounds checks.
struct Raw<'b> {
    data: &'b [u8],
    stride: usize,
    count: usize,
    ty: DataType,
    dims: usize,
    normalized: bool,
}

/// Locates an accessor's bytes, checking offsets, stride and count against the buffer view and
/// buffer. `None` for an accessor without a buffer view (its values would all be zero).
fn raw<'b>(
    acc: &Accessor<'_>,
    buffers: &'b [Vec<u8>],
    path: &Path,
    format: &'static str,
) -> IngestResult<Option<Raw<'b>>> {
    let i = acc.index();
    let err = |m: String| IngestError::parse(path, format, format!("accessor {i}: {m}"));
    if acc.sparse().is_some() {
        return Err(IngestError::Unsupported {
            path: path.to_path_buf(),
            what: format!("sparse accessor {i}"),
        });
    }
    let dims = match acc.dimensions() {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        other => {
            return Err(err(format!(
                "matrix type {other:?} where a scalar or vector was expected"
            )));
        }
    };
    let Some(view) = acc.view() else {
        return Ok(None);
    };
    let ty = acc.data_type();
    let elem = ty.size() * dims;
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(err(format!(
            "byte stride {stride} is smaller than the element size {elem}"
        )));
    }
    let buffer = buffers
        .get(view.buffer().index())
        .ok_or_else(|| err("its buffer does not exist".into()))?;
    let view_end = view
        .offset()
        .checked_add(view.length())
        .filter(|&e| e <= buffer.len());
    let Some(view_end) = view_end else {
        return Err(err(format!(
            "buffer view {} (offset {}, length {}) runs past the end of its {}-byte buffer",
            view.index(),
            view.offset(),
            view.length(),
            buffer.len()
        )));
    };
    let view_bytes = &buffer[view.offset()..view_end];
    let count = acc.count();
    if count == 0 {
        return Ok(Some(Raw {
            data: &[],
            stride,
            count,
            ty,
            dims,
            normalized: acc.normalized(),
        }));
    }
    let needed = (count - 1)
        .checked_mul(stride)
        .and_then(|n| n.checked_add(elem))
        .and_then(|n| n.checked_add(acc.offset()))
        .filter(|&n| n <= view_bytes.len());
    let Some(needed) = needed else {
        return Err(err(format!(
            "{count} elements of {elem} bytes (stride {stride}, offset {}) do not fit in its {}-byte buffer view",
            acc.offset(),
            view_bytes.len()
        )));
    };
    Ok(Some(Raw {
        data: &view_bytes[acc.offset()..needed],
        stride,
        count,
        ty,
        dims,
        normalized: acc.normalized(),
    }))
}

/// Reads a float accessor (any component type, normalised per spec) as rows of `dims` values.
/// Returns the dimension and the flattened values.
pub(crate) fn read_floats(
    acc: &Accessor<'_>,
    buffers: &[Vec<u8>],
    path: &Path,
    format: &'static str,
) -> IngestResult<Option<(usize, Vec<f32>)>> {
    let Some(raw) = raw(acc, buffers, path, format)? else {
        return Ok(None);
    };
    let size = raw.ty.size();
    let mut out = Vec::with_capacity(raw.count * raw.dims);
    for i in 0..raw.count {
        for c in 0..raw.dims {
            let at = i * raw.stride + c * size;
            out.push(component(&raw.data[at..at + size], raw.ty, raw.normalized));
        }
    }
    Ok(Some((raw.dims, out)))
}

/// Reads an index accessor (scalar u8/u16/u32).
pub(crate) fn read_indices(
    acc: &Accessor<'_>,
    buffers: &[Vec<u8>],
    path: &Path,
    format: &'static str,
) -> IngestResult<Option<Vec<u32>>> {
    let Some(raw) = raw(acc, buffers, path, format)? else {
        return Ok(None);
    };
    if raw.dims != 1 || !matches!(raw.ty, DataType::U8 | DataType::U16 | DataType::U32) {
        return Err(IngestError::parse(
            path,
            format,
            format!(
                "index accessor {} is not a scalar of unsigned bytes, shorts or ints",
                acc.index()
            ),
        ));
    }
    let size = raw.ty.size();
    Ok(Some(
        (0..raw.count)
            .map(|i| {
                let b = &raw.data[i * raw.stride..i * raw.stride + size];
                match raw.ty {
                    DataType::U8 => u32::from(b[0]),
                    DataType::U16 => u32::from(u16::from_le_bytes([b[0], b[1]])),
                    _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                }
            })
            .collect(),
    ))
}

/// One little-endian component as f32; normalised integers map to [0, 1] or [-1, 1].
#[expect(
    clippy::cast_precision_loss,
    reason = "u32 components are only used for rare quantised data"
)]
fn component(b: &[u8], ty: DataType, normalized: bool) -> f32 {
    match ty {
        DataType::I8 => {
            let v = f32::from(i8::from_le_bytes([b[0]]));
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        DataType::U8 => {
            let v = f32::from(b[0]);
            if normalized { v / 255.0 } else { v }
        }
        DataType::I16 => {
            let v = f32::from(i16::from_le_bytes([b[0], b[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = f32::from(u16::from_le_bytes([b[0], b[1]]));
            if normalized { v / 65535.0 } else { v }
        }
        DataType::U32 => {
            let v = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32;
            if normalized { v / u32::MAX as f32 } else { v }
        }
        DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}
