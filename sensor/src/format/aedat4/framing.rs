//! The compressed framing of AEDAT 4.0 packets (davis240.md §2.3): one LZ4 frame (with its
//! xxHash32 header checksum) or one Zstd frame per packet, decoded into a reused buffer that
//! never grows past a cap.

use crate::format::flatbuffer::u32_at;
use zstd::stream::raw::Operation;

/// LZ4 frame magic number.
const LZ4_MAGIC: u32 = 0x184D_2204;
/// LZ4 block size written (and the growth step of the Zstd output).
pub(super) const LZ4_BLOCK: usize = 64 << 10;

/// xxHash32 (seed 0) of an input shorter than 16 bytes: the LZ4 frame header checksum.
pub(super) fn xxh32_short(input: &[u8]) -> u32 {
    const P1: u32 = 0x9E37_79B1;
    const P2: u32 = 0x85EB_CA77;
    const P3: u32 = 0xC2B2_AE3D;
    const P4: u32 = 0x27D4_EB2F;
    const P5: u32 = 0x1656_67B1;
    debug_assert!(input.len() < 16);
    let mut h = P5.wrapping_add(input.len() as u32);
    let mut chunks = input.chunks_exact(4);
    for c in &mut chunks {
        let v = u32::from_le_bytes([c[0], c[1], c[2], c[3]]);
        h = h
            .wrapping_add(v.wrapping_mul(P3))
            .rotate_left(17)
            .wrapping_mul(P4);
    }
    for &b in chunks.remainder() {
        h = h
            .wrapping_add(u32::from(b).wrapping_mul(P5))
            .rotate_left(11)
            .wrapping_mul(P1);
    }
    h ^= h >> 15;
    h = h.wrapping_mul(P2);
    h ^= h >> 13;
    h = h.wrapping_mul(P3);
    h ^ (h >> 16)
}

/// Decodes one LZ4 frame (the LZ4 frame format: magic, FLG, BD, optional content size and
/// dictionary id, header checksum, then blocks ending with a zero size) into `dst[..n]`; `dst`
/// only grows. Blocks may be linked (each may refer to the 64 KiB before it).
pub(super) fn lz4_frame_decode(src: &[u8], dst: &mut Vec<u8>, cap: usize) -> Result<usize, String> {
    let err = |m: &str| m.to_owned();
    if u32_at(src, 0) != Some(LZ4_MAGIC) || src.len() < 7 {
        return Err(err("missing LZ4 frame magic 04 22 4D 18"));
    }
    let (flg, bd) = (src[4], src[5]);
    if flg >> 6 != 1 || flg & 0x02 != 0 || bd & 0x8F != 0 {
        return Err(format!(
            "unsupported LZ4 frame descriptor FLG {flg:#04x} BD {bd:#04x}"
        ));
    }
    let block_max = match (bd >> 4) & 7 {
        4 => 64 << 10,
        5 => 256 << 10,
        6 => 1 << 20,
        7 => 4 << 20,
        other => return Err(format!("invalid LZ4 block size code {other}")),
    };
    let independent = flg & 0x20 != 0;
    let block_checksum = if flg & 0x10 != 0 { 4 } else { 0 };
    let descriptor_end =
        6 + if flg & 0x08 != 0 { 8 } else { 0 } + if flg & 0x01 != 0 { 4 } else { 0 };
    let hc = *src
        .get(descriptor_end)
        .ok_or_else(|| err("truncated LZ4 frame header"))?;
    if hc != (xxh32_short(&src[4..descriptor_end]) >> 8) as u8 {
        return Err(err("LZ4 frame header checksum mismatch"));
    }
    let mut pos = descriptor_end + 1;
    let mut len = 0usize;
    loop {
        let word = u32_at(src, pos).ok_or_else(|| err("truncated LZ4 frame (no end mark)"))?;
        pos += 4;
        if word == 0 {
            break;
        }
        let size = (word & 0x7FFF_FFFF) as usize;
        if size > block_max {
            return Err(format!(
                "LZ4 block of {size} bytes exceeds the frame's {block_max}"
            ));
        }
        let block = src
            .get(pos..pos + size)
            .ok_or_else(|| err("truncated LZ4 block"))?;
        pos += size + block_checksum;
        if len + block_max > cap {
            return Err(format!("LZ4 frame decompresses to more than {cap} bytes"));
        }
        if dst.len() < len + block_max {
            dst.resize(len + block_max, 0);
        }
        let n = if word & 0x8000_0000 != 0 {
            dst[len..len + size].copy_from_slice(block);
            size
        } else if independent || len == 0 {
            lz4_flex::block::decompress_into(block, &mut dst[len..len + block_max])
                .map_err(|e| e.to_string())?
        } else {
            let (dict, out) = dst.split_at_mut(len);
            let dict = &dict[len.saturating_sub(LZ4_BLOCK)..];
            lz4_flex::block::decompress_into_with_dict(block, &mut out[..block_max], dict)
                .map_err(|e| e.to_string())?
        };
        len += n;
    }
    if flg & 0x04 != 0 && src.len() < pos + 4 {
        return Err(err("truncated LZ4 content checksum"));
    }
    Ok(len)
}

/// Decodes the Zstd frame(s) of `src` into `dst[..n]` with a reused decoder; `dst` only grows.
pub(super) fn zstd_decode(
    decoder: &mut zstd::stream::raw::Decoder<'static>,
    src: &[u8],
    dst: &mut Vec<u8>,
    cap: usize,
) -> Result<usize, String> {
    decoder.reinit().map_err(|e| e.to_string())?;
    let (mut read, mut len) = (0usize, 0usize);
    loop {
        if dst.len() - len < LZ4_BLOCK {
            let grown = (dst.len() * 2).max(1 << 20).min(cap);
            if grown <= dst.len() {
                return Err(format!("Zstd frame decompresses to more than {cap} bytes"));
            }
            dst.resize(grown, 0);
        }
        let status = decoder
            .run_on_buffers(&src[read..], &mut dst[len..])
            .map_err(|e| e.to_string())?;
        read += status.bytes_read;
        len += status.bytes_written;
        if status.remaining == 0 && read == src.len() {
            return Ok(len);
        }
        if status.bytes_read == 0 && status.bytes_written == 0 {
            return Err("truncated Zstd frame".to_owned());
        }
    }
}

/// Appends `src` to `dst` as one LZ4 frame (dv-processing's: independent 64 KiB blocks, no
/// checksums); incompressible blocks are stored raw.
pub(super) fn lz4_frame_encode(
    src: &[u8],
    dst: &mut Vec<u8>,
) -> Result<(), lz4_flex::block::CompressError> {
    // Frame header: FLG = version 01 | independent blocks, BD = 64 KiB blocks.
    let descriptor = [0x60u8, 0x40];
    dst.extend_from_slice(&LZ4_MAGIC.to_le_bytes());
    dst.extend_from_slice(&descriptor);
    dst.push((xxh32_short(&descriptor) >> 8) as u8);
    for block in src.chunks(LZ4_BLOCK) {
        let at = dst.len();
        let bound = lz4_flex::block::get_maximum_output_size(block.len());
        dst.resize(at + 4 + bound, 0);
        let n = lz4_flex::block::compress_into(block, &mut dst[at + 4..])?;
        let word = if n < block.len() {
            n as u32
        } else {
            // Incompressible: store the block raw (high bit set).
            dst[at + 4..at + 4 + block.len()].copy_from_slice(block);
            block.len() as u32 | 0x8000_0000
        };
        dst[at..at + 4].copy_from_slice(&word.to_le_bytes());
        dst.truncate(at + 4 + (word & 0x7FFF_FFFF) as usize);
    }
    dst.extend_from_slice(&0u32.to_le_bytes());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lz4_header_checksum_matches_dv_processing() {
        // dv-processing's LZ4 packets start 04 22 4D 18 40 40 C0.
        assert_eq!((xxh32_short(&[0x40, 0x40]) >> 8) as u8, 0xC0);
        assert_eq!(xxh32_short(&[]), 0x02CC_5D05); // the xxHash32 test vector for "" and seed 0
    }
}
