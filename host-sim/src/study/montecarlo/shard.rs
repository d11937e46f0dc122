//! Monte Carlo shard files: the file a shard writes (`--shard K/N --out FILE`), reading
//! one back, and adding up the statistics of a whole study from its shard files (every
//! shard K of one split N exactly once). Their integrity checks are [`crate::shard`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Result};
use serde::{Deserialize, Serialize};

use super::{StudySettings, StudyStats, Tally, TwoLevelStats};

/// The shard file's `format` tag.
pub const SHARD_FORMAT: &str = "camsim-montecarlo-shard";
/// The shard file's format version.
pub const SHARD_VERSION: u32 = 5;

/// Shard `index` (from 1) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// K, from 1.
    pub index: u64,
    /// N.
    pub count: u64,
}

impl Shard {
    /// The whole study as one shard.
    pub const WHOLE: Shard = Shard { index: 1, count: 1 };

    /// The sample indices of this shard among `samples`: K − 1, K − 1 + N, ...
    pub fn indices(self, samples: u64) -> impl Iterator<Item = u64> {
        (self.index - 1..samples).step_by(self.count as usize)
    }

    /// How many of `samples` this shard holds.
    pub fn len(self, samples: u64) -> u64 {
        samples
            .saturating_sub(self.index - 1)
            .div_ceil(self.count.max(1))
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// `--shard K/N`: 1 ≤ K ≤ N.
pub fn parse_shard(s: &str) -> Result<Shard, String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| "must be K/N (shard K of N, K from 1)".to_string())?;
    let k: u64 = k.trim().parse().map_err(|_| "K must be a whole number")?;
    let n: u64 = n.trim().parse().map_err(|_| "N must be a whole number")?;
    if n == 0 || k == 0 || k > n || n > 1_000_000 {
        return Err("must be K/N with 1 <= K <= N <= 1000000".into());
    }
    Ok(Shard { index: k, count: n })
}

/// A shard file: the study and the statistics of one shard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardFile {
    /// [`SHARD_FORMAT`].
    pub format: String,
    /// [`SHARD_VERSION`].
    pub version: u32,
    /// The study.
    pub study: StudySettings,
    /// Which shard.
    pub shard: Shard,
    /// Its samples (those of [`Shard::indices`]).
    pub samples: u64,
    /// Their statistics (version 3 on; version 2 held every sample's record).
    pub stats: StudyStats,
    /// A two-level study's full-model subsample among its samples (the pairs of its
    /// samples below n; version 5 on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub two_level: Option<TwoLevelStats>,
    /// The content digest of everything above (`crate::shard::digest`; version 2 on).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub digest: String,
}

/// Reads one shard file: through [`crate::shard::MAX_SHARD_BYTES`]'s limit (a larger
/// regular file is refused by its size before any byte is read) and parsed as it streams
/// in, so a file that is not JSON is refused at its first bad byte, not after reading it
/// whole.
pub fn read_shard(path: &Path) -> Result<ShardFile> {
    let reader =
        camsim_scene_file::open_limited(path, crate::shard::MAX_SHARD_BYTES, "the shard file")
            .map_err(anyhow::Error::msg)?;
    let value: serde_json::Value = serde_json::from_reader(std::io::BufReader::new(reader))
        .map_err(|e| match e.io_error_kind() {
            Some(std::io::ErrorKind::FileTooLarge) => anyhow!("{e}"),
            _ => anyhow!("{}: not JSON: {e}", path.display()),
        })?;
    if value.get("format").and_then(|f| f.as_str()) != Some(SHARD_FORMAT) {
        bail!(
            "{}: not a camsim montecarlo shard file (no \"format\": \"{SHARD_FORMAT}\")",
            path.display()
        );
    }
    let version = value.get("version").and_then(|v| v.as_u64());
    if version != Some(u64::from(SHARD_VERSION)) {
        bail!(
            "{}: shard file version {} (this camsim reads version {SHARD_VERSION})",
            path.display(),
            version.map_or("missing".into(), |v| v.to_string())
        );
    }
    // The Value's numbers are the text's, read with serde_json's float_roundtrip: every
    // number reads back bit for bit.
    let file: ShardFile = serde_json::from_value(value)
        .map_err(|e| anyhow!("{}: bad shard file: {e}", path.display()))?;
    crate::shard::verify(path, &file)?;
    Ok(file)
}

/// The first difference between two studies' settings, in words.
fn settings_difference(a: &StudySettings, b: &StudySettings) -> String {
    if a.samples != b.samples {
        return format!("--samples {} vs {}", b.samples, a.samples);
    }
    if a.seed != b.seed {
        return format!("seed {} vs {}", b.seed, a.seed);
    }
    if a.camsim_version != b.camsim_version {
        return format!("camsim {} vs {}", b.camsim_version, a.camsim_version);
    }
    if a.revolutions != b.revolutions {
        return format!("--revolutions {} vs {}", b.revolutions, a.revolutions);
    }
    if a.profile != b.profile {
        return format!("profile {:?} vs {:?}", b.profile, a.profile);
    }
    let n = |s: &StudySettings| s.two_level.as_ref().map(|t| t.full_samples);
    if n(a) != n(b) {
        let t = |s: &StudySettings| n(s).map_or("one model".into(), |n| format!("--two-level {n}"));
        return format!("{} vs {}", t(b), t(a));
    }
    if let Some((x, y)) = a.scene.lines().zip(b.scene.lines()).find(|(x, y)| x != y) {
        return format!("scene line `{}` vs `{}`", y.trim(), x.trim());
    }
    "scene".into()
}

/// The statistics of a whole study from its shard files: every file of one study (the
/// same settings), every shard K of one split N exactly once, added up.
pub fn collect(files: &[PathBuf]) -> Result<(StudySettings, Tally)> {
    let first_path = files.first().ok_or_else(|| anyhow!("no shard files"))?;
    let mut study: Option<StudySettings> = None;
    // shard K -> the file that has it, all of one split N.
    let mut owner: BTreeMap<u64, usize> = BTreeMap::new();
    let mut split: Option<(u64, usize)> = None;
    let mut stats = StudyStats::default();
    let mut two_level = TwoLevelStats::default();
    let mut seen: Vec<PathBuf> = Vec::new();
    for (f, path) in files.iter().enumerate() {
        let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
        if seen.contains(&canonical) {
            bail!("{} is given twice", path.display());
        }
        seen.push(canonical);
        let shard = read_shard(path)?;
        match &study {
            None => study = Some(shard.study.clone()),
            Some(s) if *s != shard.study => bail!(
                "{}: belongs to another study than {} ({})",
                path.display(),
                first_path.display(),
                settings_difference(s, &shard.study)
            ),
            Some(_) => {}
        }
        let Shard { index, count } = shard.shard;
        match split {
            None => split = Some((count, f)),
            Some((n, g)) if n != count => bail!(
                "{} is shard {index}/{count} and {} a shard of {n}: the shards of a study are one split K/N with one N",
                path.display(),
                files[g].display()
            ),
            Some(_) => {}
        }
        if let Some(&other) = owner.get(&index) {
            bail!(
                "shard {index}/{count} is in {} and in {} (each sample must come from exactly one shard)",
                files[other].display(),
                path.display()
            );
        }
        owner.insert(index, f);
        stats
            .merge(&shard.stats)
            .map_err(|e| anyhow!("{}: {e}", path.display()))?;
        if let Some(t) = &shard.two_level {
            two_level
                .merge(t)
                .map_err(|e| anyhow!("{}: {e}", path.display()))?;
        }
    }
    let study = study.ok_or_else(|| anyhow!("no shard files"))?;
    let n = study.samples;
    let count = split.map_or(1, |s| s.0);
    every_shard_present(&owner, count, n)?;
    anyhow::ensure!(
        stats.accounted() == n,
        "the shards hold {} samples, the study {n}",
        stats.accounted()
    );
    Ok((study, Tally { stats, two_level }))
}

/// Fails, naming the first missing samples and shards, unless every shard K of the split
/// `count` is in `owner`.
fn every_shard_present(owner: &BTreeMap<u64, usize>, count: u64, n: u64) -> Result<()> {
    let missing: Vec<u64> = (1..=count).filter(|k| !owner.contains_key(k)).collect();
    let lost: u64 = missing
        .iter()
        .map(|&k| Shard { index: k, count }.len(n))
        .sum();
    if lost > 0 {
        let mut first: Vec<u64> = missing
            .iter()
            .flat_map(|&k| Shard { index: k, count }.indices(n).take(5))
            .collect();
        first.sort_unstable();
        first.truncate(5);
        let first: Vec<String> = first.iter().map(|i| i.to_string()).collect();
        let shards: Vec<String> = missing
            .iter()
            .take(5)
            .map(|k| format!("{k}/{count}"))
            .collect();
        bail!(
            "{lost} of the study's {n} samples are missing (first: {}; shards {}); give every shard's file",
            first.join(", "),
            shards.join(", ")
        );
    }
    Ok(())
}
