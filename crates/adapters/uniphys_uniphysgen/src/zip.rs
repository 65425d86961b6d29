//! A minimal zip writer: stored (uncompressed) entries with CRC-32, fixed timestamps
//! (1980-01-01 00:00), no zip64. Enough for numpy's `np.load` of an `.npz`.

use crate::crc32::crc32;

/// Accumulates stored entries and produces the archive bytes.
#[derive(Debug, Default)]
pub(crate) struct ZipWriter {
    out: Vec<u8>,
    central: Vec<u8>,
    entries: u16,
}

/// DOS date of 1980-01-01: (year - 1980) << 9 | month << 5 | day.
const DOS_DATE: u16 = (1 << 5) | 1;

fn u16_le(out: &mut Vec<u8>, v: u16) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn u32_le(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

impl ZipWriter {
    /// Adds a stored entry; `None` if the archive would exceed zip's 4 GiB / 65535-entry limits.
    pub fn add(&mut self, name: &str, data: &[u8]) -> Option<()> {
        let offset = u32::try_from(self.out.len()).ok()?;
        let size = u32::try_from(data.len()).ok()?;
        let name_len = u16::try_from(name.len()).ok()?;
        self.entries = self.entries.checked_add(1)?;
        let crc = crc32(data);
        // Local file header.
        u32_le(&mut self.out, 0x0403_4b50);
        for v in [20, 0, 0, 0, DOS_DATE] {
            u16_le(&mut self.out, v); // version needed, flags, method (stored), time, date
        }
        for v in [crc, size, size] {
            u32_le(&mut self.out, v);
        }
        u16_le(&mut self.out, name_len);
        u16_le(&mut self.out, 0);
        self.out.extend_from_slice(name.as_bytes());
        self.out.extend_from_slice(data);
        u32::try_from(self.out.len()).ok()?;
        // Central directory record.
        u32_le(&mut self.central, 0x0201_4b50);
        for v in [20, 20, 0, 0, 0, DOS_DATE] {
            u16_le(&mut self.central, v); // made by, needed, flags, method, time, date
        }
        for v in [crc, size, size] {
            u32_le(&mut self.central, v);
        }
        for v in [name_len, 0, 0, 0, 0] {
            u16_le(&mut self.central, v); // name, extra, comment, disk, internal attributes
        }
        u32_le(&mut self.central, 0); // external attributes
        u32_le(&mut self.central, offset);
        self.central.extend_from_slice(name.as_bytes());
        Some(())
    }

    /// The archive bytes; `None` past zip's 4 GiB limit.
    pub fn finish(mut self) -> Option<Vec<u8>> {
        let central_offset = u32::try_from(self.out.len()).ok()?;
        let central_size = u32::try_from(self.central.len()).ok()?;
        self.out.extend_from_slice(&self.central);
        u32_le(&mut self.out, 0x0605_4b50);
        for v in [0, 0, self.entries, self.entries] {
            u16_le(&mut self.out, v);
        }
        u32_le(&mut self.out, central_size);
        u32_le(&mut self.out, central_offset);
        u16_le(&mut self.out, 0);
        Some(self.out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_entry_archive_has_the_hand_computed_layout() {
        let mut zip = ZipWriter::default();
        zip.add("a.txt", b"hi").unwrap();
        let bytes = zip.finish().unwrap();
        // Local header 30 + name 5 + data 2 = 37; central 46 + 5 = 51; end record 22.
        assert_eq!(bytes.len(), 37 + 51 + 22);
        assert_eq!(&bytes[..4], b"PK\x03\x04");
        assert_eq!(&bytes[30..37], b"a.txthi");
        // CRC-32 of "hi" is 0xD8932AAC, little-endian at offset 14.
        assert_eq!(&bytes[14..18], &0xD893_2AACu32.to_le_bytes());
        let end = &bytes[88..];
        assert_eq!(&end[..4], b"PK\x05\x06");
        assert_eq!(u16::from_le_bytes([end[10], end[11]]), 1);
        assert_eq!(u32::from_le_bytes([end[16], end[17], end[18], end[19]]), 37);
    }
}
