//! The integrity of `camsim montecarlo` shard files: a content digest over the header and
//! the records, written with the shard and checked at `merge`, and sanity checks on the
//! header and on every record.
//!
//! A shard (version 3) holds its samples' statistics, not their records
//! (`crate::stats::study`). The digest is 128-bit FNV-1a over the shard's JSON as written
//! without its `digest` key (serde_json writes every `f64` in its shortest round-trip form, so a shard read
//! back and written again gives the same bytes). It catches corruption (a truncated
//! copy, a flipped bit) and casual edits (one number changed by hand); it is not a
//! signature: anyone who edits a shard and recomputes the digest with this code gets a
//! shard that merges. The sanity checks refuse values no run produces (a negative RMS,
//! a contact force minimum above its maximum, zero solver steps, histogram counts that
//! do not add up to the samples) whatever the digest.

use std::path::Path;

use anyhow::{bail, Result};

use crate::study::montecarlo::{Shard, ShardFile};

/// The digest's name in the file, before the hexadecimal value.
pub const DIGEST_PREFIX: &str = "fnv1a-128:";

/// Most bytes of a shard file read: 256 MB. A shard holds statistics, not records: its
/// size grows with the histogram bins occupied, not with the samples (measured: 26 609
/// bins over 61 columns in a 1.43 MB shard, about 54 bytes a bin, see BENCHMARKS.md,
/// "Memory of a Monte Carlo study"; at most 1 024 bins a factor of two of each column's
/// range). 256 MB is 4.7 million bins, 77 000 a column: 75 factors of two of every
/// column's range filled, more than any study's columns span. A larger file is not a
/// shard this camsim wrote: refused by its size before reading (a device or a pipe is
/// read through the limit), so a junk file never reaches hundreds of MB of memory.
pub const MAX_SHARD_BYTES: u64 = 256_000_000;

/// 128-bit FNV-1a of `bytes`.
fn fnv1a_128(bytes: &[u8]) -> u128 {
    const OFFSET: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
    const PRIME: u128 = 0x0000_0000_0100_0000_0000_0000_0000_013b;
    bytes
        .iter()
        .fold(OFFSET, |h, b| (h ^ u128::from(*b)).wrapping_mul(PRIME))
}

/// The digest of a shard: over its JSON without the `digest` key.
pub fn digest(file: &ShardFile) -> Result<String> {
    let mut bare = serde_json::to_value(file)?;
    if let Some(o) = bare.as_object_mut() {
        o.remove("digest");
    }
    // serde_json's maps keep the struct's key order (preserve_order off: sorted keys,
    // the same for writer and reader either way).
    let bytes = serde_json::to_vec(&bare)?;
    Ok(format!("{DIGEST_PREFIX}{:032x}", fnv1a_128(&bytes)))
}

/// Checks a shard read from `path`: its header, its digest, every record. Errors are one
/// line naming the file.
pub fn verify(path: &Path, file: &ShardFile) -> Result<()> {
    let name = path.display();
    check_header(file.shard, file.study.samples).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
    let want = digest(file)?;
    if file.digest.is_empty() {
        bail!("{name}: the shard has no digest (written by another camsim, or edited)");
    }
    if file.digest != want {
        bail!(
            "{name}: the shard's digest does not match its content: the file was changed after it was written (corrupted or edited); run the shard again"
        );
    }
    let want = file.shard.len(file.study.samples);
    if file.samples != want {
        bail!(
            "{name}: shard {} of a study of {} samples holds {want} samples, not {}",
            file.shard,
            file.study.samples,
            file.samples
        );
    }
    file.stats
        .check(file.samples)
        .map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
    match (&file.study.two_level, &file.two_level) {
        (None, None) => {}
        (Some(t), Some(stats)) => {
            let n = file.shard.len(t.full_samples.min(file.study.samples));
            stats
                .check(n)
                .map_err(|e| anyhow::anyhow!("{name}: full-model subsample: {e}"))?;
        }
        (Some(_), None) => {
            bail!("{name}: a two-level study's shard without its full-model subsample")
        }
        (None, Some(_)) => bail!("{name}: a full-model subsample in a study of one model"),
    }
    Ok(())
}

/// A shard header K/N of a study of `samples` samples: at least one sample, 1 ≤ K ≤ N
/// (a shard beyond the samples is empty, not wrong).
pub fn check_header(shard: Shard, samples: u64) -> Result<()> {
    let Shard { index, count } = shard;
    if samples == 0 {
        bail!("the study has 0 samples");
    }
    if count == 0 || index == 0 || index > count {
        bail!("shard {index}/{count}: must be K/N with 1 <= K <= N");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_128_matches_the_published_vectors() {
        // The FNV reference (www.isthe.com/chongo/tech/comp/fnv): "" is the offset basis,
        // "a" the first step by hand.
        assert_eq!(fnv1a_128(b""), 0x6c62272e07bb014262b821756295c58d);
        let by_hand = (0x6c62272e07bb014262b821756295c58du128 ^ 0x61)
            .wrapping_mul(0x0000000001000000000000000000013b);
        assert_eq!(fnv1a_128(b"a"), by_hand);
        assert_eq!(fnv1a_128(b"a"), 0xd228cb696f1a8caf78912b704e4a8964);
    }

    #[test]
    fn headers_outside_k_of_n_are_refused() {
        let h = |index, count| Shard { index, count };
        assert!(check_header(h(1, 1), 1).is_ok());
        assert!(check_header(h(3, 3), 7).is_ok());
        for (s, n) in [(h(0, 0), 5), (h(5, 3), 7), (h(0, 3), 7), (h(1, 1), 0)] {
            assert!(check_header(s, n).is_err(), "{s:?} of {n}");
        }
    }
}
