//! The few flatbuffer reads AEDAT 4.0 needs (davis240.md §2.3), every one bounds-checked: a
//! corrupt offset yields `None`, never a panic.
//!
//! Layout facts used: a buffer starts with the root table's `u32` offset, then a 4-byte file
//! identifier; a table starts with an `i32` offset back to its vtable (`vtable = table − soffset`);
//! a vtable holds `u16` vtable size, `u16` table size, then one `u16` field offset per field (0 =
//! absent); vectors and strings are reached through a `u32` offset relative to the field's own
//! position and start with a `u32` length.

/// A view of one flatbuffer.
#[derive(Clone, Copy)]
pub(crate) struct Buffer<'a>(pub(crate) &'a [u8]);

/// A table inside a [`Buffer`].
#[derive(Clone, Copy)]
pub(crate) struct Table<'a> {
    buf: &'a [u8],
    pos: usize,
    vtable: usize,
    vtable_len: usize,
}

fn u16_at(b: &[u8], pos: usize) -> Option<u16> {
    Some(u16::from_le_bytes(
        b.get(pos..pos.checked_add(2)?)?.try_into().ok()?,
    ))
}

pub(crate) fn u32_at(b: &[u8], pos: usize) -> Option<u32> {
    Some(u32::from_le_bytes(
        b.get(pos..pos.checked_add(4)?)?.try_into().ok()?,
    ))
}

fn i64_at(b: &[u8], pos: usize) -> Option<i64> {
    Some(i64::from_le_bytes(
        b.get(pos..pos.checked_add(8)?)?.try_into().ok()?,
    ))
}

impl<'a> Buffer<'a> {
    /// The 4-byte file identifier.
    pub(crate) fn identifier(self) -> Option<&'a [u8]> {
        self.0.get(4..8)
    }

    /// The root table.
    pub(crate) fn root(self) -> Option<Table<'a>> {
        let pos = u32_at(self.0, 0)? as usize;
        Table::at(self.0, pos)
    }
}

impl<'a> Table<'a> {
    fn at(buf: &'a [u8], pos: usize) -> Option<Self> {
        let soffset = i32::from_le_bytes(buf.get(pos..pos.checked_add(4)?)?.try_into().ok()?);
        let vtable = (pos as i64).checked_sub(i64::from(soffset))?;
        let vtable = usize::try_from(vtable).ok()?;
        let vtable_len = usize::from(u16_at(buf, vtable)?);
        if vtable_len < 4 || vtable.checked_add(vtable_len)? > buf.len() {
            return None;
        }
        Some(Self {
            buf,
            pos,
            vtable,
            vtable_len,
        })
    }

    /// Absolute position of field `id`, or `None` when absent.
    fn field(&self, id: usize) -> Option<usize> {
        let entry = 4 + 2 * id;
        if entry + 2 > self.vtable_len {
            return None;
        }
        match u16_at(self.buf, self.vtable + entry)? {
            0 => None,
            off => self.pos.checked_add(usize::from(off)),
        }
    }

    /// Field `id` as `i32`; `Some(default)` when absent, `None` when out of bounds.
    pub(crate) fn i32_or(&self, id: usize, default: i32) -> Option<i32> {
        match self.field(id) {
            None => Some(default),
            Some(p) => Some(u32_at(self.buf, p)? as i32),
        }
    }

    /// Field `id` as `i64`; `Some(default)` when absent, `None` when out of bounds.
    pub(crate) fn i64_or(&self, id: usize, default: i64) -> Option<i64> {
        match self.field(id) {
            None => Some(default),
            Some(p) => i64_at(self.buf, p),
        }
    }

    /// Field `id` as a vector of `elem_size`-byte structs: `(count, bytes)`; an absent field is
    /// an empty vector.
    pub(crate) fn struct_vector(&self, id: usize, elem_size: usize) -> Option<(usize, &'a [u8])> {
        let Some(p) = self.field(id) else {
            return Some((0, &[]));
        };
        let start = p.checked_add(u32_at(self.buf, p)? as usize)?;
        let count = u32_at(self.buf, start)? as usize;
        let bytes = count.checked_mul(elem_size)?;
        let data = self.buf.get(start + 4..(start + 4).checked_add(bytes)?)?;
        Some((count, data))
    }

    /// Field `id` as a string's bytes (absent: empty).
    pub(crate) fn string(&self, id: usize) -> Option<&'a [u8]> {
        Some(self.struct_vector(id, 1)?.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corrupt_offsets_are_none_not_panics() {
        assert!(Buffer(&[]).root().is_none());
        assert!(
            Buffer(&[0xFF, 0xFF, 0xFF, 0x7F, 0, 0, 0, 0])
                .root()
                .is_none()
        );
        // Root at 8, soffset pointing before the buffer.
        let b = [8u8, 0, 0, 0, b'E', b'V', b'T', b'S', 0x40, 0, 0, 0];
        assert!(Buffer(&b).root().is_none());
        // A valid table (vtable at 10, table at 16) whose vector offset points past the end.
        let b = [
            16u8, 0, 0, 0, b'E', b'V', b'T', b'S', 0, 0, // root offset, identifier, padding
            6, 0, 8, 0, 4, 0, // vtable: 6 bytes, table 8 bytes, field 0 at +4
            6, 0, 0, 0, 0xE8, 0x03, 0, 0, // table: soffset 6, field 0 = 1000
        ];
        let root = Buffer(&b).root().unwrap();
        assert_eq!(Buffer(&b).identifier(), Some(&b"EVTS"[..]));
        assert_eq!(root.i32_or(0, -1), Some(1000));
        assert_eq!(root.i64_or(1, -1), Some(-1)); // absent field → default
        assert!(root.struct_vector(0, 16).is_none());
        assert!(root.string(0).is_none());
    }
}
