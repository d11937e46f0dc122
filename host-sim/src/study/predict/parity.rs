//! Parity with the firmware: the `parity ...` lines the chip logs, computed from the host's
//! f32 run, and their comparison with a decoded defmt log, line by line.

use anyhow::{bail, Result};

use camsim_chip::ParityLine;

use super::Prediction;

/// The `parity ...` lines the firmware prints, in its order, from the host's f32 run
/// (the text of [`ParityLine`], the type the firmware logs with defmt).
pub fn parity_lines(p: &Prediction<f32>) -> Vec<String> {
    let mut out = Vec::new();
    for (i, (rpm, s)) in p.table.rpm.iter().zip(p.table.at.iter()).enumerate() {
        out.push(ParityLine::table(i as u32, *rpm, s));
    }
    out.push(ParityLine::jump(p.table.jump_rpm));
    for c in &p.checks {
        out.push(ParityLine::check(c.rpm, &c.direct));
    }
    for (i, s) in p.samples.iter().enumerate() {
        let i = i as u32;
        out.push(match &s.prediction {
            Some(q) => ParityLine::sample(i, q, s.alarm),
            None => ParityLine::reading(i, &s.reading, s.alarm),
        });
    }
    out.iter().map(ParityLine::to_string).collect()
}

/// The `parity ...` lines of a decoded firmware log (text from `parity ` to the line end).
pub fn log_parity_lines(log: &str) -> Vec<String> {
    log.lines()
        .filter_map(|l| l.find("parity ").map(|i| l[i..].trim_end().to_string()))
        .collect()
}

/// Compares the firmware's parity lines with the host's; Err names the first difference.
pub fn check_parity(log: &str, host: &[String]) -> Result<usize> {
    let fw = log_parity_lines(log);
    for (k, (f, h)) in fw.iter().zip(host.iter()).enumerate() {
        if f != h {
            bail!(
                "parity mismatch at parity line {} of {}: firmware `{f}` != host `{h}`",
                k + 1,
                host.len()
            );
        }
    }
    if fw.len() != host.len() {
        bail!(
            "parity: the firmware log has {} parity lines, the host {}",
            fw.len(),
            host.len()
        );
    }
    Ok(fw.len())
}
