//! The `.npy` format, version 1.0: magic, a Python-dict header padded to 64 bytes, raw
//! little-endian C-order data.

/// An `.npy` file of raw little-endian `data` with numpy type `descr` (e.g. `<f4`) and `shape`.
pub(crate) fn npy(descr: &str, shape: &[usize], data: &[u8]) -> Vec<u8> {
    let shape = match shape {
        [n] => format!("({n},)"),
        dims => format!(
            "({})",
            dims.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    // magic (6) + version (2) + header length (2) + header + '\n' is a multiple of 64.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + data.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    // Headers here are well below 64 KiB (a few hundred bytes).
    out.extend_from_slice(
        &u16::try_from(header.len())
            .unwrap_or(u16::MAX)
            .to_le_bytes(),
    );
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(data);
    out
}

/// `float32 [N, 3]`.
pub(crate) fn npy_f32_rows(rows: &[[f32; 3]]) -> Vec<u8> {
    let data: Vec<u8> = rows
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    npy("<f4", &[rows.len(), 3], &data)
}

/// `uint8 [N, 3]`.
pub(crate) fn npy_u8_rows(rows: &[[u8; 3]]) -> Vec<u8> {
    let data: Vec<u8> = rows.iter().flatten().copied().collect();
    npy("|u1", &[rows.len(), 3], &data)
}

/// A numpy unicode array `<U{n}` (UTF-32LE, `n` = longest string in characters, at least 1).
pub(crate) fn npy_unicode(strings: &[String]) -> Vec<u8> {
    let width = strings
        .iter()
        .map(|s| s.chars().count())
        .max()
        .unwrap_or(0)
        .max(1);
    let mut data = Vec::with_capacity(strings.len() * width * 4);
    for s in strings {
        let mut n = 0;
        for c in s.chars() {
            data.extend_from_slice(&u32::from(c).to_le_bytes());
            n += 1;
        }
        data.resize(data.len() + (width - n) * 4, 0);
    }
    npy(&format!("<U{width}"), &[strings.len()], &data)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_is_padded_to_64_bytes_and_ends_with_a_newline() {
        let bytes = npy_f32_rows(&[[1.0, 2.0, 3.0]]);
        assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
        let header_len = usize::from(u16::from_le_bytes([bytes[8], bytes[9]]));
        assert_eq!((10 + header_len) % 64, 0);
        assert_eq!(bytes[10 + header_len - 1], b'\n');
        let header = std::str::from_utf8(&bytes[10..10 + header_len]).unwrap();
        assert!(header.starts_with("{'descr': '<f4', 'fortran_order': False, 'shape': (1, 3), }"));
        assert_eq!(
            &bytes[10 + header_len..],
            &[0, 0, 128, 63, 0, 0, 0, 64, 0, 0, 64, 64]
        );
    }

    #[test]
    fn unicode_array_is_utf32_padded_to_the_longest_string() {
        let bytes = npy_unicode(&["2".to_owned(), "10".to_owned()]);
        let header_len = usize::from(u16::from_le_bytes([bytes[8], bytes[9]]));
        let header = std::str::from_utf8(&bytes[10..10 + header_len]).unwrap();
        assert!(header.contains("'descr': '<U2'") && header.contains("'shape': (2,)"));
        let data = &bytes[10 + header_len..];
        assert_eq!(
            data,
            &[b'2', 0, 0, 0, 0, 0, 0, 0, b'1', 0, 0, 0, b'0', 0, 0, 0]
        );
    }
}
