//! The bench's plots, drawn with plotters (text in the embedded DejaVu Sans, so no system font
//! library is needed): the paper's Fig. 7 — speedup of candidates/s over naive against the
//! candidate-set size per chain, trees and reject chains per scene view — and the error
//! against time on log–log axes, one line per method: the mean over the repeats, with the 95 %
//! interval as error bars when there are several.

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;

use crate::results::{along_time, final_interval, first_seen, views, Row};
use smlt::render::Method;

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

fn register_font() {
    REGISTER.call_once(|| {
        // The font is embedded and known good; a failure here would show as missing text only.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Fig. 7: speedup of candidates/s over naive (final measurements) against candidates per
/// chain (2^d − 1 for s<d>, l for rc<l>), on a log axis; the path estimator's trees and reject
/// chains over path-naive.
pub fn speedup_plot(rows: &[Row], path: &Path) -> anyhow::Result<()> {
    register_font();
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let speed = |r: &Row| r.mutations_per_s;
    // Each family over the naive chains of its own estimator.
    let families = [
        ("SMLT", "s", "naive"),
        ("RCMLT", "rc", "naive"),
        ("SMLT path", "path-s", "path-naive"),
        ("RCMLT path", "path-rc", "path-naive"),
    ];
    for (scene, view) in views(rows) {
        let methods =
            first_seen(rows.iter().filter(|r| r.scene == scene && r.view == view).map(|r| r.method.as_str()));
        for (family, prefix, base) in families {
            let Some(naive) = final_interval(rows, &scene, view, base, speed) else { continue };
            let mut points = vec![(1.0, 1.0)];
            for name in methods.iter().filter(|m| m.starts_with(prefix)) {
                let (Ok(Method::Metropolis { schedule, .. }), Some(x)) =
                    (name.parse::<Method>(), final_interval(rows, &scene, view, name, speed))
                else {
                    continue;
                };
                points.push((schedule.candidates_per_chain() as f64, x.mean / naive.mean));
            }
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            if points.len() > 1 {
                series.push((format!("{family} {scene} v{view}"), points));
            }
        }
    }
    let y_max = series.iter().flat_map(|(_, p)| p.iter().map(|x| x.1)).fold(1.0, f64::max) * 1.1;
    let root = BitMapBackend::new(path, (900, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("Speedup of candidates/s over naive", ("sans-serif", 24))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d((1f64..64f64).log_scale(), 0f64..y_max)?;
    chart
        .configure_mesh()
        .x_desc("candidates per chain (2^d - 1, or l)")
        .y_desc("speedup")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .draw()?;
    for (i, (label, points)) in series.into_iter().enumerate() {
        let colour = Palette99::pick(i).to_rgba();
        let dashed = label.starts_with("RC");
        chart
            .draw_series(LineSeries::new(points.clone(), colour.stroke_width(if dashed { 1 } else { 3 })))?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3)));
        chart.draw_series(points.into_iter().map(|p| Circle::new(p, 4, colour.filled())))?;
    }
    chart.configure_series_labels().background_style(WHITE.mix(0.85)).border_style(BLACK).draw()?;
    root.present()?;
    Ok(())
}

/// RMSE against render time for one scene view, log–log, one line per method (the mean over
/// the repeats, with error bars of the 95 % interval).
pub fn error_plot(rows: &[Row], scene: &str, view: u32, path: &Path) -> anyhow::Result<()> {
    register_font();
    let mine: Vec<&Row> =
        rows.iter().filter(|r| r.scene == scene && r.view == view && r.errors.rmse > 0.0).collect();
    if mine.is_empty() {
        return Ok(());
    }
    let methods = first_seen(mine.iter().map(|r| r.method.as_str()));
    let curves: Vec<Vec<(f64, crate::interval::Interval)>> =
        methods.iter().map(|m| along_time(rows, scene, view, m, |r| r.errors.rmse)).collect();
    let (mut t0, mut t1, mut e0, mut e1) = (f64::MAX, 0.0f64, f64::MAX, 0.0f64);
    for (t, e) in curves.iter().flatten() {
        t0 = t0.min(*t);
        t1 = t1.max(*t);
        e0 = e0.min(e.low.max(e.mean * 0.5));
        e1 = e1.max(e.high);
    }
    let root = BitMapBackend::new(path, (900, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("RMSE against time: {scene} view {view}"), ("sans-serif", 24))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        // A log axis shows labels only across a decade or more.
        .build_cartesian_2d(
            (t0 * 0.9..t1 * 1.1).log_scale(),
            ((e0 * 0.8).min(e1 * 0.125)..e1 * 1.25).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("render seconds")
        .y_desc("RMSE")
        .y_labels(12)
        .y_label_formatter(&|v| format!("{v:.3}"))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .draw()?;
    for (i, (m, curve)) in methods.iter().zip(&curves).enumerate() {
        let colour = Palette99::pick(i).to_rgba();
        let points: Vec<(f64, f64)> = curve.iter().map(|(t, e)| (*t, e.mean)).collect();
        chart
            .draw_series(LineSeries::new(points, colour.stroke_width(2)))?
            .label(m.to_string())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3)));
        chart.draw_series(curve.iter().filter(|(_, e)| e.n > 1).map(|(t, e)| {
            ErrorBar::new_vertical(*t, e.low.max(e0), e.mean, e.high, colour.stroke_width(1), 6)
        }))?;
    }
    chart.configure_series_labels().background_style(WHITE.mix(0.85)).border_style(BLACK).draw()?;
    root.present()?;
    Ok(())
}

/// Writes the plots of `rows` into `out`: `speedup.png` and one `error_<scene>_v<view>.png` per
/// scene view.
pub fn plot(rows: &[Row], out: &Path) -> anyhow::Result<()> {
    speedup_plot(rows, &out.join("speedup.png"))?;
    for (scene, view) in views(rows) {
        error_plot(rows, &scene, view, &out.join(format!("error_{scene}_v{view}.png")))?;
    }
    Ok(())
}
