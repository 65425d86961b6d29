//! The binary glTF container: a 12-byte header, a JSON chunk padded with spaces and an optional
//! BIN chunk padded with zeros, every chunk 4-byte aligned.

use crate::ExamplesError;

const MAGIC: &[u8; 4] = b"glTF";
const VERSION: u32 = 2;
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;
const HEADER_LEN: usize = 12;
const CHUNK_HEADER_LEN: usize = 8;

/// Packs a glTF JSON document and its binary buffer into GLB bytes. An empty `bin` writes no BIN
/// chunk.
pub(crate) fn pack_glb(json: &[u8], bin: &[u8]) -> Result<Vec<u8>, ExamplesError> {
    let json_len = padded_len(json.len());
    let bin_len = padded_len(bin.len());
    let bin_chunk_len = if bin.is_empty() {
        0
    } else {
        CHUNK_HEADER_LEN + bin_len
    };
    let total = HEADER_LEN + CHUNK_HEADER_LEN + json_len + bin_chunk_len;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&to_u32(total, "file length")?.to_le_bytes());
    write_chunk(&mut out, CHUNK_JSON, json, json_len, b' ')?;
    if !bin.is_empty() {
        write_chunk(&mut out, CHUNK_BIN, bin, bin_len, 0)?;
    }
    Ok(out)
}

fn write_chunk(
    out: &mut Vec<u8>,
    kind: u32,
    data: &[u8],
    padded: usize,
    pad: u8,
) -> Result<(), ExamplesError> {
    out.extend_from_slice(&to_u32(padded, "chunk length")?.to_le_bytes());
    out.extend_from_slice(&kind.to_le_bytes());
    out.extend_from_slice(data);
    out.resize(out.len() + padded - data.len(), pad);
    Ok(())
}

/// `n` rounded up to a multiple of four.
pub(crate) fn padded_len(n: usize) -> usize {
    n.div_ceil(4) * 4
}

/// `n` as `u32`, or [`ExamplesError::TooLarge`].
pub(crate) fn to_u32(n: usize, what: &'static str) -> Result<u32, ExamplesError> {
    u32::try_from(n).map_err(|_| ExamplesError::TooLarge { what })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn word(bytes: &[u8], at: usize) -> u32 {
        u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
    }

    #[test]
    fn chunks_are_padded_to_four_bytes_with_spaces_and_zeros() {
        let glb = pack_glb(b"{\"a\":1}", &[1, 2, 3, 4, 5]).unwrap();
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(word(&glb, 4), 2);
        assert_eq!(word(&glb, 8) as usize, glb.len());
        assert_eq!(glb.len() % 4, 0);
        assert_eq!(word(&glb, 12), 8);
        assert_eq!(word(&glb, 16), CHUNK_JSON);
        assert_eq!(&glb[20..28], b"{\"a\":1} ");
        assert_eq!(word(&glb, 28), 8);
        assert_eq!(word(&glb, 32), CHUNK_BIN);
        assert_eq!(&glb[36..44], &[1, 2, 3, 4, 5, 0, 0, 0]);
    }

    #[test]
    fn empty_binary_buffer_writes_no_bin_chunk() {
        let glb = pack_glb(b"{}", &[]).unwrap();
        assert_eq!(glb.len(), HEADER_LEN + CHUNK_HEADER_LEN + 4);
    }
}
