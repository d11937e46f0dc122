//! The integrity of `camsim montecarlo` shard files: a content digest over the header and
//! the records, written with the shard and checked at `merge`, and sanity checks on the
//! header and on every record.
//!
//! The digest is 128-bit FNV-1a over the shard's JSON as written without its `digest`
//! key (serde_json writes every `f64` in its shortest round-trip form, so a shard read
//! back and written again gives the same bytes). It catches corruption (a truncated
//! copy, a flipped bit) and casual edits (one number changed by hand); it is not a
//! signature: anyone who edits a shard and recomputes the digest with this code gets a
//! shard that merges. The sanity checks refuse values no run produces (a negative RMS,
//! a contact force minimum above its maximum, zero solver steps) whatever the digest.

use std::path::Path;

use anyhow::{bail, Result};

use crate::study::montecarlo::{SampleRecord, Shard, ShardFile, COLUMNS};

/// The digest's name in the file, before the hexadecimal value.
pub const DIGEST_PREFIX: &str = "fnv1a-128:";

/// Most bytes of a shard file read: 8 GB. A record is about 1.5 kB of JSON (measured:
/// a 20-sample shard of the reference study is 30.9 kB, header included), so this holds
/// a shard of the largest study run without `--allow-long` (4 million samples, about
/// 6 GB: `camsim::study_limits`); a larger file is not a shard this camsim wrote, and a
/// device is not read without end.
pub const MAX_SHARD_BYTES: u64 = 8_000_000_000;

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
    let Shard { index, count } = file.shard;
    for r in &file.records {
        if r.index % count != index - 1 {
            bail!(
                "{name}: sample {} does not belong to shard {index}/{count}",
                r.index
            );
        }
        check_record(r).map_err(|e| anyhow::anyhow!("{name}: sample {}: {e}", r.index))?;
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

/// What every record of a run satisfies: steps taken, a finite non-negative RMS
/// deviation, periods with finite values, non-negative RMS columns and stress, and each
/// minimum at most its average and maximum.
pub fn check_record(r: &SampleRecord) -> Result<()> {
    if r.steps == 0 {
        bail!("steps = 0: every run takes solver steps");
    }
    if !(r.rms_deviation_in.is_finite() && r.rms_deviation_in >= 0.0) {
        bail!(
            "rms_deviation_in = {}: must be finite and not negative",
            r.rms_deviation_in
        );
    }
    if r.periods.is_empty() {
        bail!("no periods");
    }
    let col = |name: &str| COLUMNS.iter().position(|c| *c == name);
    for p in &r.periods {
        for (c, v) in COLUMNS.iter().zip(p.values.iter()) {
            if !v.is_finite() {
                bail!("period {}: {c} = {v}: not finite", p.period);
            }
            if (c.starts_with("rms_") || *c == "contact_stress_max") && *v < 0.0 {
                bail!("period {}: {c} = {v}: must not be negative", p.period);
            }
        }
        for (lo, mid, hi) in [
            (
                "contact_force_min",
                "contact_force_avg",
                "contact_force_max",
            ),
            ("torque_min", "torque_avg", "torque_max"),
        ] {
            let get = |n: &str| col(n).and_then(|i| p.values.get(i)).copied();
            if let (Some(a), Some(m), Some(b)) = (get(lo), get(mid), get(hi)) {
                if !(a <= m && m <= b) {
                    bail!(
                        "period {}: {lo} = {a}, {mid} = {m}, {hi} = {b}: the minimum must not exceed the average or the maximum",
                        p.period
                    );
                }
            }
        }
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
