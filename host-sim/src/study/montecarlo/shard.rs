//! Monte Carlo shard files: the file a shard writes (`--shard K/N --out FILE`), reading
//! one back, and collecting the records of a whole study from its shard files (every
//! sample exactly once). Their integrity checks are [`crate::shard`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Result};
use serde::{Deserialize, Serialize};

use super::{SampleRecord, Shard, StudySettings, SHARD_FORMAT, SHARD_VERSION};

/// A shard file: the study and the records of one shard.
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
    /// Its records, by index.
    pub records: Vec<SampleRecord>,
    /// The content digest of everything above (`crate::shard::digest`; version 2 on).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub digest: String,
}

/// Reads one shard file.
pub fn read_shard(path: &Path) -> Result<ShardFile> {
    let text = camsim_scene_file::read_text(path, crate::shard::MAX_SHARD_BYTES, "the shard file")
        .map_err(anyhow::Error::msg)?;
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| anyhow!("{}: not JSON: {e}", path.display()))?;
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
    // Parsed from the text (not the Value) so that every number reads back bit for bit.
    let file: ShardFile = serde_json::from_str(&text)
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
    if let Some((x, y)) = a.scene.lines().zip(b.scene.lines()).find(|(x, y)| x != y) {
        return format!("scene line `{}` vs `{}`", y.trim(), x.trim());
    }
    "scene".into()
}

/// The records of a whole study from its shard files: every file of one study (the same
/// settings), every sample exactly once, sorted by index.
pub fn collect(files: &[PathBuf]) -> Result<(StudySettings, Vec<SampleRecord>)> {
    let first_path = files.first().ok_or_else(|| anyhow!("no shard files"))?;
    let mut study: Option<StudySettings> = None;
    // index -> the file that has it.
    let mut owner: BTreeMap<u64, usize> = BTreeMap::new();
    let mut records: Vec<SampleRecord> = Vec::new();
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
        let n = shard.study.samples;
        for r in shard.records {
            anyhow::ensure!(
                r.index < n,
                "{}: sample {} is outside the study's 0..{n}",
                path.display(),
                r.index
            );
            if let Some(&other) = owner.get(&r.index) {
                bail!(
                    "sample {} is in {} and in {} (each sample must come from exactly one shard)",
                    r.index,
                    files[other].display(),
                    path.display()
                );
            }
            owner.insert(r.index, f);
            records.push(r);
        }
    }
    let study = study.ok_or_else(|| anyhow!("no shard files"))?;
    let n = study.samples;
    if owner.len() as u64 != n {
        let missing: Vec<String> = (0..n)
            .filter(|i| !owner.contains_key(i))
            .take(5)
            .map(|i| i.to_string())
            .collect();
        bail!(
            "{} of the study's {n} samples are missing (first: {}); give every shard's file",
            n - owner.len() as u64,
            missing.join(", ")
        );
    }
    records.sort_by_key(|r| r.index);
    Ok((study, records))
}
