//! Seed hashes: the two integer hashes neurotac derives its seeds with, written once.
//!
//! | hash | function | used for |
//! |---|---|---|
//! | FNV-1a, 64 bit (Fowler–Noll–Vo; offset basis `0xcbf29ce484222325`, prime `0x100000001b3`) | [`fnv1a`], [`Fnv1a`] (incremental) | stable hashes of names and parameters into seeds and keys: a texture's name → its sample and mounting, a dataset's metadata → its cache key, a run's spikes → a checksum |
//! | SplitMix64 (Steele, Lea & Flood 2014, "Fast splittable pseudorandom number generators", OOPSLA) | [`splitmix64`] | seed mixing: one well-mixed 64-bit value from a seed combined (xor) with a label or an index, so that neighbouring seeds give unrelated streams |
//!
//! Both are pure functions of their input on every platform (bytes are hashed in the order
//! given; no `std::hash::Hasher`, whose integer methods use the native byte order), so a seed
//! derived here is the same on every machine and every run. Neither is cryptographic.
//!
//! ```
//! use neurotac_core::seed_hash::{fnv1a, splitmix64};
//! let texture = fnv1a("grid 5 mm".as_bytes());
//! let stream = splitmix64(42 ^ splitmix64(texture));
//! assert_ne!(stream, splitmix64(43 ^ splitmix64(texture)));
//! ```

/// FNV-1a's 64-bit offset basis: the hash of no bytes.
pub const FNV1A_OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a's 64-bit prime, 2⁴⁰ + 2⁸ + 0xb3.
pub const FNV1A_PRIME: u64 = 0x0000_0100_0000_01b3;

/// SplitMix64's increment γ: the odd integer nearest 2⁶⁴/φ (φ the golden ratio).
pub const SPLITMIX64_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// FNV-1a, 64 bit, of `bytes`: for each byte, xor it into the hash, then multiply by
/// [`FNV1A_PRIME`] (wrapping), starting from [`FNV1A_OFFSET_BASIS`].
///
/// ```
/// use neurotac_core::seed_hash::fnv1a;
/// assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
/// assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
/// ```
#[inline]
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut hash = Fnv1a::new();
    hash.write(bytes);
    hash.finish()
}

/// FNV-1a, 64 bit, fed in pieces: writing `a` then `b` gives [`fnv1a`] of `a` followed by `b`.
///
/// ```
/// use neurotac_core::seed_hash::{Fnv1a, fnv1a};
/// let mut hash = Fnv1a::new();
/// hash.write(&7u32.to_le_bytes());
/// hash.write(&0.5f64.to_bits().to_le_bytes());
/// let mut whole = 7u32.to_le_bytes().to_vec();
/// whole.extend(0.5f64.to_bits().to_le_bytes());
/// assert_eq!(hash.finish(), fnv1a(&whole));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fnv1a(u64);

impl Fnv1a {
    /// A hash of no bytes yet ([`FNV1A_OFFSET_BASIS`]).
    #[inline]
    pub const fn new() -> Self {
        Self(FNV1A_OFFSET_BASIS)
    }

    /// Hashes `bytes`, in order, after those written before.
    #[inline]
    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(FNV1A_PRIME);
        }
    }

    /// The hash of every byte written so far.
    #[inline]
    pub const fn finish(&self) -> u64 {
        self.0
    }
}

impl Default for Fnv1a {
    fn default() -> Self {
        Self::new()
    }
}

/// SplitMix64's output for the state `z`: `z + γ` ([`SPLITMIX64_GAMMA`], wrapping) through its
/// finaliser (xor-shift 30, multiply, xor-shift 27, multiply, xor-shift 31). Calling it on
/// `seed`, `seed + γ`, `seed + 2γ`, … yields the SplitMix64 sequence of `seed`; on its own it
/// mixes one 64-bit value into another with every input bit affecting every output bit.
///
/// ```
/// use neurotac_core::seed_hash::splitmix64;
/// assert_eq!(splitmix64(0), 0xe220_a839_7b1d_cdaf);
/// ```
#[inline]
pub fn splitmix64(z: u64) -> u64 {
    let mut z = z.wrapping_add(SPLITMIX64_GAMMA);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_the_published_test_vectors() {
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }

    /// Values of the sensor's former texture key (a fold over the name's bytes), computed with
    /// that code before it was replaced: mountings and natural samples keep their seeds.
    #[test]
    fn fnv1a_of_texture_names_keeps_the_former_seeds() {
        assert_eq!(fnv1a(b"grid 5 mm"), 0x7873_4554_53ad_5954);
        assert_eq!(fnv1a(b"denim"), 0x3fb6_1075_e16b_f34e);
    }

    /// The bench checksum's former loop (one byte at a time over a `u32` and an `f64`'s bits,
    /// little-endian), computed before it was replaced.
    #[test]
    fn incremental_fnv1a_keeps_the_former_checksum() {
        let mut hash = Fnv1a::default();
        hash.write(&7u32.to_le_bytes());
        hash.write(&0.5f64.to_bits().to_le_bytes());
        assert_eq!(hash.finish(), 0x7356_f8f9_0b90_ab6b);
    }

    /// Values of the former `mix64` (sensor) and `mix` (experiments), computed with that code
    /// before it was replaced.
    #[test]
    fn splitmix64_keeps_the_former_mix_values() {
        assert_eq!(splitmix64(0), 0xe220_a839_7b1d_cdaf);
        assert_eq!(splitmix64(1), 0x910a_2dec_8902_5cc1);
        assert_eq!(splitmix64(42), 0xbdd7_3226_2feb_6e95);
        assert_eq!(splitmix64(0x6d65_6368), 0xe6ee_9107_f58f_31ff);
        assert_eq!(splitmix64(u64::MAX), 0xe4d9_7177_1b65_2c20);
    }

    /// Vigna's reference `splitmix64.c` seeded with 1234567.
    #[test]
    fn splitmix64_steps_give_the_reference_sequence() {
        let outputs: Vec<u64> = (0..3u64)
            .map(|k| splitmix64(1_234_567u64.wrapping_add(k.wrapping_mul(SPLITMIX64_GAMMA))))
            .collect();
        assert_eq!(
            outputs,
            [
                6_457_827_717_110_365_317,
                3_203_168_211_198_807_973,
                9_817_491_932_198_370_423
            ]
        );
    }
}
