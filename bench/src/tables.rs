//! The bench's Markdown tables: the paper's Table 3 and Table 4 with RMSE, relMSE and
//! efficiency (means over the repeats with 95 % intervals, the best marked only where its
//! interval overlaps no other), and the references' own noise.

use std::fmt::Write as _;

use crate::interval::{clear_best, Interval};
use crate::results::{final_interval, views, Row};
use crate::BenchSettings;
use smlt::render::{Estimator, Method};

/// The paper's Table 3 (million mutations/s) and Table 4 (PSNR after the full time), with RMSE
/// and relMSE, as Markdown: methods down, scene views across, each cell the mean over the
/// repeats of the final measurements with its 95 % interval; a cell is bold where that method
/// is best and its interval overlaps no other method's.
/// `blind`: (scene, view, method, why) of each method that cannot render some of a view's
/// light ([`smlt::render::blind_spot`]): its cells are marked † and the reason follows.
pub fn tables(
    methods: &[String],
    seconds: f64,
    rows: &[Row],
    blind: &[(String, u32, String, String)],
) -> String {
    let columns = views(rows);
    let repeats = rows.iter().map(|r| r.repeat + 1).max().unwrap_or(1);
    let mut out = format!(
        "Every cell: the mean over {repeats} independent run(s){}; **bold**: best, with an interval that overlaps no other method's.\n\n",
        if repeats > 1 { " ± the half-width of its 95 % confidence interval (Student t)" } else { "" }
    );
    let header = columns.iter().map(|(s, v)| format!(" {s} v{v} |")).collect::<String>();
    let rule = "---|".repeat(columns.len());
    type Value = fn(&Row) -> f64;
    // (title, value of a row, decimals, higher is better, shown as the reciprocal of the mean).
    let tables: [(String, Value, usize, bool, bool); 6] = [
        (
            "Million mutations (candidates; a peer's paths) per second".into(),
            |r| r.mutations_per_s / 1e6,
            3,
            true,
            false,
        ),
        (
            "Speedup of mutations/s over naive (path-*: over path-naive; ratio of the means)".into(),
            |r| r.mutations_per_s,
            2,
            true,
            false,
        ),
        (format!("PSNR (dB, peak 1 on clamped values) after {seconds} s"), |r| r.errors.psnr, 2, true, false),
        (format!("RMSE after {seconds} s"), |r| r.errors.rmse, 4, false, false),
        (format!("relMSE after {seconds} s"), |r| r.errors.relmse, 4, false, false),
        (
            format!(
                "Efficiency 1 / (relMSE × seconds) after {seconds} s (of the mean relMSE × seconds; the interval is its reciprocal's)"
            ),
            |r| r.errors.relmse * r.seconds,
            3,
            true,
            true,
        ),
    ];
    for (t, (title, value, decimals, higher, reciprocal)) in tables.iter().enumerate() {
        let _ = writeln!(out, "### {title}\n\n| method |{header}\n|---|{rule}");
        let cells: Vec<Vec<Option<Interval>>> = methods
            .iter()
            .map(|m| {
                let shown = |i: Interval| if *reciprocal { i.reciprocal() } else { i };
                columns.iter().map(|(s, v)| final_interval(rows, s, *v, m, value).map(shown)).collect()
            })
            .collect();
        let best: Vec<Option<usize>> = (0..columns.len())
            .map(|c| {
                let column: Vec<Interval> = cells.iter().filter_map(|m| m[c]).collect();
                if t == 1 || column.len() != cells.len() {
                    return None;
                }
                clear_best(&column, *higher)
            })
            .collect();
        for (i, m) in methods.iter().enumerate() {
            let text: String = (0..columns.len())
                .map(|c| match (t, cells[i][c]) {
                    (_, None) => " — |".to_string(),
                    // Over the naive chains of the same estimator; paths per second (the path
                    // tracer's, a peer's) are not candidates per second of a chain.
                    (1, Some(x)) => match speedup_baseline(m) {
                        Some(base) => final_interval(rows, &columns[c].0, columns[c].1, base, value)
                            .map_or(" — |".to_string(), |n| format!(" {:.2}× |", x.mean / n.mean)),
                        None => " — |".to_string(),
                    },
                    (_, Some(x)) if best[c] == Some(i) => format!(" **{}** |", x.show(*decimals)),
                    (_, Some(x)) => format!(" {} |", x.show(*decimals)),
                })
                .zip(&columns)
                .map(|(cell, (s, v))| {
                    if blind.iter().any(|(bs, bv, bm, _)| bs == s && bv == v && bm == m) {
                        cell.replacen(" |", " † |", 1)
                    } else {
                        cell
                    }
                })
                .collect();
            let _ = writeln!(out, "| {m} |{text}");
        }
        out.push('\n');
    }
    for (s, v, m, why) in blind {
        let _ = writeln!(out, "† {s} v{v}, {m}: {why}.\n");
    }
    out
}

/// The method a row's candidates/s speedup is measured against: the naive chains of its own
/// estimator; None for the path tracer and for peers.
pub fn speedup_baseline(method: &str) -> Option<&'static str> {
    match method.parse::<Method>() {
        Ok(Method::PathTracer) | Err(_) => None,
        Ok(Method::Metropolis { estimator: Estimator::Path, .. }) => Some("path-naive"),
        Ok(Method::Metropolis { estimator: Estimator::Multiplexed, .. }) => Some("naive"),
    }
}

/// estimated reference RMSE and the smallest final RMSE of any method.
pub fn reference_table(b: &BenchSettings, rows: &[Row], noises: &[(String, u32, Option<f64>)]) -> String {
    let source = match &b.reference {
        Some(path) => format!("external: {}, not rendered by this bench", path.display()),
        None => format!("{} spp", b.reference_spp),
    };
    let mut out = format!(
        "### References ({source}; noise = estimated RMSE of the reference itself)\n\n\
         | scene view | reference noise | smallest method RMSE after {} s | ratio |\n|---|---|---|---|\n",
        b.seconds
    );
    for (scene, view, noise) in noises {
        let best = b
            .methods
            .iter()
            .filter_map(|m| final_interval(rows, scene, *view, &m.to_string(), |r| r.errors.rmse))
            .map(|i| i.mean)
            .fold(f64::INFINITY, f64::min);
        let _ = match noise {
            Some(n) => writeln!(
                out,
                "| {scene} v{view} | {} | {} | {:.2} |",
                significant(*n),
                significant(best),
                n / best
            ),
            None => writeln!(out, "| {scene} v{view} | — | {} | — |", significant(best)),
        };
    }
    out.push('\n');
    out
}

/// `x` with three significant digits in fixed notation (0.000227, 0.0222, 1.50): a reference's
/// noise and an error span orders of magnitude that four decimals would cut to 0.0002.
pub fn significant(x: f64) -> String {
    if !(x.is_finite() && x > 0.0) {
        return format!("{x}");
    }
    let decimals = (2 - x.log10().floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three significant digits at every scale, none cut by a fixed number of decimals.
    #[test]
    fn noise_keeps_three_significant_digits() {
        assert_eq!(significant(2.2706e-4), "0.000227");
        assert_eq!(significant(0.022215), "0.0222");
        assert_eq!(significant(1.5), "1.50");
        assert_eq!(significant(123.4), "123");
        assert_eq!(significant(0.0), "0");
    }

    /// Speedups are over the naive chains of the same estimator; the path tracer and peers
    /// trace paths, not candidates of chains, and get none.
    #[test]
    fn speedups_compare_chains_of_one_estimator() {
        for (method, base) in [
            ("s3", Some("naive")),
            ("rc16", Some("naive")),
            ("naive", Some("naive")),
            ("path-s3", Some("path-naive")),
            ("path-rc4", Some("path-naive")),
            ("pt", None),
            ("mitsuba-path", None),
        ] {
            assert_eq!(speedup_baseline(method), base, "{method}");
        }
    }

    /// The references' table says where the reference came from: rendered at its spp, or an
    /// external file the bench did not render (whose own noise it knows only from an `smlt
    /// reference` sidecar: `tests/cli.rs`).
    #[test]
    fn the_reference_table_names_an_external_reference() {
        let mut b = BenchSettings {
            scenes: vec![("cornell".into(), 1)],
            methods: vec![smlt::render::MethodChoice::Named(Method::NAIVE)],
            render: smlt::render::Settings { width: 4, height: 4, max_depth: 3, ..Default::default() },
            seconds: 2.0,
            reference_spp: 512,
            candidates: None,
            tessellation: 1,
            environment: None,
            threads: 1,
            repeats: 1,
            reference: None,
            out: "out".into(),
        };
        let noises = [("cornell".to_string(), 1, Some(0.01))];
        assert!(reference_table(&b, &[], &noises).contains("### References (512 spp;"));
        b.reference = Some("mine.exr".into());
        let table = reference_table(&b, &[], &[("cornell".to_string(), 1, None)]);
        assert!(
            table.contains("external: mine.exr, not rendered by this bench") && !table.contains("512 spp"),
            "{table}"
        );
        assert!(table.contains("| cornell v1 | — |"), "{table}");
    }
}
