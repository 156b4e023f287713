//! The compression of VBA project streams, [MS-OVBA] 2.4.1: a signature byte, then chunks of
//! at most 4096 decompressed bytes, each either stored raw or as LZ77 tokens (a flag byte per
//! eight tokens; a token is a literal byte or a copy of earlier bytes of the same chunk).

/// Why a compressed container cannot be read, with the byte where it went wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OvbaError {
    pub offset: usize,
    pub message: String,
    /// The container inflates past the bound it was read with.
    pub past_limit: bool,
}

impl std::fmt::Display for OvbaError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "byte {}: {}", self.offset, self.message)
    }
}

const CHUNK: usize = 4096;

fn fail<T>(offset: usize, message: impl Into<String>) -> Result<T, OvbaError> {
    Err(OvbaError { offset, message: message.into(), past_limit: false })
}

/// The most bytes one stream decompresses to: the VBA editor holds at most 65,535 lines of
/// 1,023 characters in a module, under 64 MiB, so a container that inflates past that (a
/// chunk's 4,096 bytes from 3 compressed ones, about 1,365 times) is hostile or corrupt.
pub const MAX_DECOMPRESSED: usize = 64 << 20;

/// Decompresses a CompressedContainer (2.4.1.3.1), refusing one that inflates past
/// [`MAX_DECOMPRESSED`].
pub fn decompress(data: &[u8]) -> Result<Vec<u8>, OvbaError> {
    decompress_at_most(data, MAX_DECOMPRESSED)
}

/// [`decompress`] with the bound given: checked after each chunk, which adds at most 4,096.
pub fn decompress_at_most(data: &[u8], limit: usize) -> Result<Vec<u8>, OvbaError> {
    match data.first() {
        Some(1) => {}
        Some(b) => return fail(0, format!("compressed container starts with {b:#04x}, not 0x01")),
        None => return fail(0, "compressed container is empty"),
    }
    let mut out = Vec::with_capacity(data.len().min(limit) * 2);
    let mut at = 1;
    while at < data.len() {
        let chunk = at;
        at = decompress_chunk(data, at, &mut out)?;
        if out.len() > limit {
            let mib = limit >> 20;
            let message = format!("decompresses to more than {mib} MiB (a VBA module holds less)");
            return Err(OvbaError { offset: chunk, message, past_limit: true });
        }
    }
    Ok(out)
}

/// Decompresses the chunk starting at `at` onto `out`; returns where the next chunk starts.
fn decompress_chunk(data: &[u8], at: usize, out: &mut Vec<u8>) -> Result<usize, OvbaError> {
    let Some(header) = data.get(at..at + 2) else {
        return fail(at, "chunk header cut short");
    };
    let header = u16::from_le_bytes([header[0], header[1]]);
    let size = usize::from(header & 0x0FFF) + 3;
    if (header >> 12) & 0b111 != 0b011 {
        return fail(at, "chunk header has a wrong signature");
    }
    let compressed = header & 0x8000 != 0;
    if at + size > data.len() {
        return fail(at, format!("chunk of {size} bytes cut short ({} bytes left)", data.len() - at));
    }
    let end = at + size;
    let body = at + 2;
    if !compressed {
        let Some(raw) = data.get(body..body + CHUNK) else {
            return fail(body, "raw chunk shorter than 4096 bytes");
        };
        out.extend_from_slice(raw);
        return Ok(body + CHUNK);
    }
    let start = out.len();
    let mut pos = body;
    while pos < end {
        let flags = data[pos];
        pos += 1;
        for bit in 0..8 {
            if pos >= end {
                break;
            }
            if flags & (1 << bit) == 0 {
                out.push(data[pos]);
                pos += 1;
                continue;
            }
            let Some(token) = data.get(pos..pos + 2).filter(|_| pos + 2 <= end) else {
                return fail(pos, "copy token cut short");
            };
            let token = u16::from_le_bytes([token[0], token[1]]);
            let (offset, length) = unpack_copy_token(token, out.len() - start);
            if offset > out.len() - start {
                return fail(pos, format!("copy token reaches {offset} bytes back, before the chunk"));
            }
            if out.len() - start + length > CHUNK {
                return fail(at, "chunk decompresses to more than 4096 bytes");
            }
            for _ in 0..length {
                out.push(out[out.len() - offset]);
            }
            pos += 2;
        }
    }
    if out.len() - start > CHUNK {
        return fail(at, "chunk decompresses to more than 4096 bytes");
    }
    Ok(end)
}

/// The number of bits of a copy token that hold the offset, given how many bytes the chunk
/// has decompressed so far (2.4.1.3.19.1).
fn offset_bits(decompressed: usize) -> u32 {
    let bits = usize::BITS - decompressed.saturating_sub(1).leading_zeros();
    bits.max(4)
}

fn unpack_copy_token(token: u16, decompressed: usize) -> (usize, usize) {
    let bits = offset_bits(decompressed);
    let length_mask = 0xFFFFu16 >> bits;
    let length = usize::from(token & length_mask) + 3;
    let offset = usize::from((token & !length_mask) >> (16 - bits)) + 1;
    (offset, length)
}

fn pack_copy_token(offset: usize, length: usize, decompressed: usize) -> u16 {
    let bits = offset_bits(decompressed);
    (((offset - 1) as u16) << (16 - bits)) | (length - 3) as u16
}

/// Compresses `data` into a CompressedContainer (2.4.1.3.6), finding the longest earlier
/// match for each position as the specification's compressor does.
///
/// A whole 4096-byte chunk that does not shrink is stored raw; a shorter last chunk has no raw
/// form (a raw chunk holds 4096 bytes), so one that does not fit its size field (some 3640
/// bytes with hardly a repeat: no source text) is an error, not a corrupt header.
pub fn compress(data: &[u8]) -> Result<Vec<u8>, OvbaError> {
    let mut out = vec![1u8];
    for (n, chunk) in data.chunks(CHUNK).enumerate() {
        compress_chunk(chunk, &mut out).map_err(|()| OvbaError {
            offset: n * CHUNK,
            message: format!("the last {} bytes do not compress into one chunk", chunk.len()),
            past_limit: false,
        })?;
    }
    Ok(out)
}

fn compress_chunk(chunk: &[u8], out: &mut Vec<u8>) -> Result<(), ()> {
    let tokens = tokens_of(chunk);
    if tokens.len() > CHUNK && chunk.len() == CHUNK {
        // No gain: a raw chunk (only possible for a whole 4096-byte chunk).
        out.extend_from_slice(&(0x3FFFu16).to_le_bytes());
        out.extend_from_slice(chunk);
        return Ok(());
    }
    if tokens.len() > CHUNK {
        return Err(());
    }
    let size = (tokens.len() + 2 - 3) as u16;
    out.extend_from_slice(&(0xB000 | size).to_le_bytes());
    out.extend_from_slice(&tokens);
    Ok(())
}

/// The token sequences of one chunk (flag bytes included).
fn tokens_of(chunk: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(chunk.len() + chunk.len() / 8 + 1);
    let mut pos = 0;
    while pos < chunk.len() {
        let flag_at = out.len();
        out.push(0);
        for bit in 0..8 {
            if pos >= chunk.len() {
                break;
            }
            match longest_match(chunk, pos) {
                Some((offset, length)) => {
                    out[flag_at] |= 1 << bit;
                    out.extend_from_slice(&pack_copy_token(offset, length, pos).to_le_bytes());
                    pos += length;
                }
                None => {
                    out.push(chunk[pos]);
                    pos += 1;
                }
            }
        }
    }
    out
}

/// The longest run before `pos` that repeats at `pos` (at least 3 bytes), as (offset, length).
fn longest_match(chunk: &[u8], pos: usize) -> Option<(usize, usize)> {
    let bits = offset_bits(pos);
    let max_length = (0xFFFFusize >> bits) + 3;
    let mut best: Option<(usize, usize)> = None;
    for candidate in (0..pos).rev() {
        let length =
            (0..max_length.min(chunk.len() - pos)).take_while(|&i| chunk[candidate + i] == chunk[pos + i]).count();
        if length >= 3 && best.is_none_or(|(_, l)| length > l) {
            best = Some((pos - candidate, length));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [MS-OVBA] 3.2.1, "No Compression": the specification's own example.
    #[test]
    fn decompresses_the_specifications_examples() {
        let plain = b"abcdefghijklmnopqrstuv.";
        let container = [
            0x01, 0x19, 0xB0, 0x00, 0x61, 0x62, 0x63, 0x64, 0x65, 0x66, 0x67, 0x68, 0x00, 0x69, 0x6A, 0x6B, 0x6C, 0x6D,
            0x6E, 0x6F, 0x70, 0x00, 0x71, 0x72, 0x73, 0x74, 0x75, 0x76, 0x2E,
        ];
        assert_eq!(decompress(&container).unwrap(), plain);
        // 3.2.2, "Normal Compression".
        let plain = b"#aaabcdefaaaaghijaaaaaklaaamnopqaaaaaaaaaaaarstuvwxyzaaa";
        let container = [
            0x01, 0x2F, 0xB0, 0x00, 0x23, 0x61, 0x61, 0x61, 0x62, 0x63, 0x64, 0x65, 0x82, 0x66, 0x00, 0x70, 0x61, 0x67,
            0x68, 0x69, 0x6A, 0x01, 0x38, 0x08, 0x61, 0x6B, 0x6C, 0x00, 0x30, 0x6D, 0x6E, 0x6F, 0x70, 0x06, 0x71, 0x02,
            0x70, 0x04, 0x10, 0x72, 0x73, 0x74, 0x75, 0x76, 0x10, 0x77, 0x78, 0x79, 0x7A, 0x00, 0x3C,
        ];
        assert_eq!(decompress(&container).unwrap(), plain);
    }

    #[test]
    fn compressing_then_decompressing_gives_the_input_back() {
        let text: Vec<u8> =
            (0..20_000u32).map(|i| b"Sub Main()\r\n  x = 1\r\nEnd Sub\r\n"[(i % 29) as usize]).collect();
        for len in [0, 1, 3, 100, 4095, 4096, 4097, 9000, 20_000] {
            let packed = compress(&text[..len]).unwrap();
            assert_eq!(decompress(&packed).unwrap(), &text[..len], "length {len}");
        }
        let noise: Vec<u8> = (0..9000u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8).collect();
        assert_eq!(decompress(&compress(&noise).unwrap()).unwrap(), noise);
        // 4000 bytes without a repeat fit no chunk: 4000 literals and 500 flag bytes.
        let mut state = 0x1234_5678u32;
        let last: Vec<u8> = (0..4000)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                (state >> 24) as u8
            })
            .collect();
        assert!(tokens_of(&last).len() > CHUNK);
        assert!(compress(&last).unwrap_err().message.contains("do not compress"));
    }

    #[test]
    fn a_container_inflating_past_the_bound_is_refused_after_the_chunk_that_passed_it() {
        // Raw chunks of 4,096 bytes each: 3 of them pass a bound of 10,000.
        let mut data = vec![1u8];
        for _ in 0..3 {
            data.extend_from_slice(&0x3FFFu16.to_le_bytes());
            data.extend(std::iter::repeat_n(b'x', CHUNK));
        }
        assert_eq!(decompress_at_most(&data, 3 * CHUNK).unwrap().len(), 3 * CHUNK);
        let e = decompress_at_most(&data, 10_000).unwrap_err();
        assert_eq!(e.offset, 1 + 2 * (CHUNK + 2));
        assert!(e.message.contains("decompresses to more than"), "{e}");
    }

    #[test]
    fn broken_containers_are_errors_with_the_byte() {
        assert_eq!(decompress(&[]).unwrap_err().offset, 0);
        assert!(decompress(&[2, 0, 0]).unwrap_err().message.contains("0x02"));
        assert!(decompress(&[1, 0x19]).unwrap_err().message.contains("cut short"));
        // A copy token at the chunk's start reaches before it.
        assert!(decompress(&[1, 0x02, 0xB0, 0x01, 0x00, 0x00]).unwrap_err().message.contains("before the chunk"));
    }
}
