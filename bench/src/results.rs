//! The bench's measurements as rows: one per method, scene view, repeat and time — their CSV
//! (`results.csv`, read back by its header), and the selections the tables and plots make of
//! them (each repeat's final row, intervals over repeats, curves along time).

use crate::interval::Interval;
use crate::metrics::Errors;

/// One measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The scene's label: a generated scene's name or a glTF file's stem.
    pub scene: String,
    /// The view: 1-based index among the scene's cameras.
    pub view: u32,
    /// The method as printed: `naive`, `s<d>` or `rc<l>`.
    pub method: String,
    /// Which of the independent repeats (0-based; its seed is the bench's seed + repeat).
    pub repeat: u32,
    /// Render seconds so far.
    pub seconds: f64,
    /// Candidates traced so far.
    pub candidates: u64,
    /// Chain steps so far.
    pub steps: f64,
    /// Candidates per second.
    pub mutations_per_s: f64,
    /// Chain steps per second.
    pub steps_per_s: f64,
    /// Errors against the reference.
    pub errors: Errors,
    /// Candidates rejected so far for a NaN or infinite contribution (never splatted).
    pub nan_inf: u64,
    /// The normalisation b so far (bootstrap and large steps pooled).
    pub b: f64,
    /// b's standard error relative to b.
    pub b_rel_se: f64,
}

/// The CSV header of `results.csv`.
pub const CSV_HEADER: &str =
    "scene,view,method,repeat,seconds,candidates,steps,mutations_per_s,steps_per_s,rmse,relmse,psnr,nan_inf,b,b_rel_se";

impl Row {
    /// The row as CSV.
    pub fn csv(&self) -> String {
        format!(
            "{},{},{},{},{:.3},{},{:.0},{:.1},{:.1},{:.6e},{:.6e},{:.3},{},{:.6e},{:.4e}",
            self.scene,
            self.view,
            self.method,
            self.repeat,
            self.seconds,
            self.candidates,
            self.steps,
            self.mutations_per_s,
            self.steps_per_s,
            self.errors.rmse,
            self.errors.relmse,
            self.errors.psnr,
            self.nan_inf,
            self.b,
            self.b_rel_se
        )
    }
}

/// Reads the rows of a `results.csv` by its header's column names (the `repeat`, NaN/Inf and b
/// columns may be absent, as in files written before they existed).
pub fn read_csv(text: &str) -> anyhow::Result<Vec<Row>> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name);
    let required = [
        "scene",
        "view",
        "method",
        "seconds",
        "candidates",
        "steps",
        "mutations_per_s",
        "steps_per_s",
        "rmse",
        "relmse",
        "psnr",
    ];
    if let Some(missing) = required.iter().find(|n| column(n).is_none()) {
        anyhow::bail!("line 1: no column {missing} (not a results.csv of smlt bench)");
    }
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != header.len() {
            anyhow::bail!("line {}: {} fields, the header has {}", i + 2, f.len(), header.len());
        }
        let text = |name: &str| column(name).map(|k| f[k]);
        let num = |name: &str| -> anyhow::Result<Option<f64>> {
            match text(name) {
                Some(v) => {
                    v.parse::<f64>().map(Some).map_err(|e| anyhow::anyhow!("line {}, {name}: {e}", i + 2))
                }
                None => Ok(None),
            }
        };
        let need = |name: &str| -> anyhow::Result<f64> { Ok(num(name)?.expect("required column")) };
        rows.push(Row {
            scene: text("scene").unwrap_or_default().to_string(),
            view: need("view")? as u32,
            method: text("method").unwrap_or_default().to_string(),
            repeat: num("repeat")?.unwrap_or(0.0) as u32,
            seconds: need("seconds")?,
            candidates: need("candidates")? as u64,
            steps: need("steps")?,
            mutations_per_s: need("mutations_per_s")?,
            steps_per_s: need("steps_per_s")?,
            errors: Errors { rmse: need("rmse")?, relmse: need("relmse")?, psnr: need("psnr")? },
            nan_inf: num("nan_inf")?.unwrap_or(0.0) as u64,
            b: num("b")?.unwrap_or(f64::NAN),
            b_rel_se: num("b_rel_se")?.unwrap_or(f64::NAN),
        });
    }
    Ok(rows)
}

/// Each repeat's last measurement of `method` on a scene view.
pub fn finals<'a>(rows: &'a [Row], scene: &str, view: u32, method: &str) -> Vec<&'a Row> {
    let mut out: Vec<&Row> = Vec::new();
    for r in rows.iter().filter(|r| r.scene == scene && r.view == view && r.method == method) {
        match out.iter_mut().find(|x| x.repeat == r.repeat) {
            Some(x) => *x = r,
            None => out.push(r),
        }
    }
    out
}

/// The 95 % interval over repeats of a final measurement of `method` (None if it never ran).
pub fn final_interval(
    rows: &[Row],
    scene: &str,
    view: u32,
    method: &str,
    value: impl Fn(&Row) -> f64,
) -> Option<Interval> {
    let values: Vec<f64> = finals(rows, scene, view, method).into_iter().map(value).collect();
    (!values.is_empty()).then(|| Interval::of(&values))
}

/// The measurements of `method` on a scene view along time: for the k-th measurement time,
/// the mean render seconds and the interval of `value` over the repeats.
pub fn along_time(
    rows: &[Row],
    scene: &str,
    view: u32,
    method: &str,
    value: impl Fn(&Row) -> f64,
) -> Vec<(f64, Interval)> {
    let mine: Vec<&Row> =
        rows.iter().filter(|r| r.scene == scene && r.view == view && r.method == method).collect();
    let mut repeats: Vec<u32> = mine.iter().map(|r| r.repeat).collect();
    repeats.sort_unstable();
    repeats.dedup();
    let series: Vec<Vec<&Row>> =
        repeats.iter().map(|k| mine.iter().copied().filter(|r| r.repeat == *k).collect()).collect();
    let points = series.iter().map(Vec::len).min().unwrap_or(0);
    (0..points)
        .map(|i| {
            let at: Vec<&Row> = series.iter().map(|s| s[i]).collect();
            let seconds = at.iter().map(|r| r.seconds).sum::<f64>() / at.len() as f64;
            (seconds, Interval::of(&at.iter().map(|r| value(r)).collect::<Vec<f64>>()))
        })
        .collect()
}

/// The last measurement of `method` on a scene view.
pub fn final_row<'a>(rows: &'a [Row], scene: &str, view: u32, method: &str) -> Option<&'a Row> {
    rows.iter().rfind(|r| r.scene == scene && r.view == view && r.method == method)
}

/// The distinct items of `items` in the order they first appear (the order of the tables'
/// columns and the plots' series: as measured).
pub fn first_seen<T: PartialEq>(items: impl IntoIterator<Item = T>) -> Vec<T> {
    let mut out = Vec::new();
    for item in items {
        if !out.contains(&item) {
            out.push(item);
        }
    }
    out
}

/// The scene views of `rows`, as measured.
pub fn views(rows: &[Row]) -> Vec<(String, u32)> {
    first_seen(rows.iter().map(|r| (r.scene.clone(), r.view)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(method: &str, repeat: u32, seconds: f64, rmse: f64) -> Row {
        Row {
            scene: "s".into(),
            view: 1,
            method: method.into(),
            repeat,
            seconds,
            candidates: 1,
            steps: 1.0,
            mutations_per_s: 1.0,
            steps_per_s: 1.0,
            errors: Errors { rmse, relmse: rmse, psnr: 1.0 },
            nan_inf: 0,
            b: 1.0,
            b_rel_se: 0.01,
        }
    }

    /// Repeats are summarised per measurement time and at the end; the CSV round-trips, and a
    /// file from before the `repeat` column reads as one repeat.
    #[test]
    fn repeats_are_summarised_and_read_back() {
        let rows = vec![
            row("naive", 0, 1.0, 0.4),
            row("naive", 0, 2.1, 0.2),
            row("naive", 1, 1.1, 0.6),
            row("naive", 1, 2.0, 0.4),
        ];
        let curve = along_time(&rows, "s", 1, "naive", |r| r.errors.rmse);
        assert_eq!(curve.len(), 2);
        assert!((curve[0].0 - 1.05).abs() < 1e-12 && (curve[0].1.mean - 0.5).abs() < 1e-12);
        let end = final_interval(&rows, "s", 1, "naive", |r| r.errors.rmse).unwrap();
        assert_eq!((end.n, end.mean), (2, 0.30000000000000004));
        let text = rows.iter().fold(format!("{CSV_HEADER}\n"), |s, r| s + &r.csv() + "\n");
        assert_eq!(read_csv(&text).unwrap().len(), 4);
        let old = "scene,view,method,seconds,candidates,steps,mutations_per_s,steps_per_s,rmse,relmse,psnr\n\
                   s,1,naive,1.0,10,10,1.0,1.0,0.5,0.5,6.0\n";
        let old = read_csv(old).unwrap();
        assert_eq!((old[0].repeat, old[0].errors.rmse, old[0].nan_inf), (0, 0.5, 0));
        assert!(read_csv("a,b\n1,2\n").is_err());
    }
}
