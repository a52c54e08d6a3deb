//! The bench's plots, drawn with plotters (text in the embedded DejaVu Sans, so no system font
//! library is needed): the seed's Fig. 7 — speedup of candidates/s over naive against the
//! candidate-set size per chain, trees and reject chains per scene view — and the error
//! against time on log–log axes, one line per method.

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;

use crate::bench::Row;
use crate::render::Method;

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

fn register_font() {
    REGISTER.call_once(|| {
        // The font is embedded and known good; a failure here would show as missing text only.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

fn views(rows: &[Row]) -> Vec<(String, u32)> {
    let mut v: Vec<(String, u32)> = Vec::new();
    for r in rows {
        if !v.contains(&(r.scene.clone(), r.view)) {
            v.push((r.scene.clone(), r.view));
        }
    }
    v
}

fn last<'a>(rows: &'a [Row], scene: &str, view: u32, method: &str) -> Option<&'a Row> {
    rows.iter().rfind(|r| r.scene == scene && r.view == view && r.method == method)
}

/// Fig. 7: speedup of candidates/s over naive (final measurements) against candidates per
/// chain (2^d − 1 for s<d>, l for rc<l>), on a log axis.
pub fn speedup_plot(rows: &[Row], path: &Path) -> anyhow::Result<()> {
    register_font();
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for (scene, view) in views(rows) {
        let Some(naive) = last(rows, &scene, view, "naive") else { continue };
        for (family, prefix) in [("SMLT", 's'), ("RCMLT", 'r')] {
            let mut points = vec![(1.0, 1.0)];
            for r in
                rows.iter().filter(|r| r.scene == scene && r.view == view && r.method.starts_with(prefix))
            {
                if last(rows, &scene, view, &r.method).map(|x| std::ptr::eq(x, r)) != Some(true) {
                    continue;
                }
                if let Ok(m) = r.method.parse::<Method>() {
                    points.push((m.candidates_per_chain() as f64, r.mutations_per_s / naive.mutations_per_s));
                }
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

/// RMSE against render time for one scene view, log–log, one line per method.
pub fn error_plot(rows: &[Row], scene: &str, view: u32, path: &Path) -> anyhow::Result<()> {
    register_font();
    let mine: Vec<&Row> =
        rows.iter().filter(|r| r.scene == scene && r.view == view && r.errors.rmse > 0.0).collect();
    if mine.is_empty() {
        return Ok(());
    }
    let (mut t0, mut t1, mut e0, mut e1) = (f64::MAX, 0.0f64, f64::MAX, 0.0f64);
    for r in &mine {
        t0 = t0.min(r.seconds);
        t1 = t1.max(r.seconds);
        e0 = e0.min(r.errors.rmse);
        e1 = e1.max(r.errors.rmse);
    }
    let root = BitMapBackend::new(path, (900, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("RMSE against time: {scene} view {view}"), ("sans-serif", 24))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((t0 * 0.9..t1 * 1.1).log_scale(), (e0 * 0.8..e1 * 1.25).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("render seconds")
        .y_desc("RMSE")
        .y_labels(12)
        .y_label_formatter(&|v| format!("{v:.3}"))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .draw()?;
    let mut methods: Vec<&str> = Vec::new();
    for r in &mine {
        if !methods.contains(&r.method.as_str()) {
            methods.push(&r.method);
        }
    }
    for (i, m) in methods.iter().enumerate() {
        let colour = Palette99::pick(i).to_rgba();
        let points: Vec<(f64, f64)> =
            mine.iter().filter(|r| r.method == *m).map(|r| (r.seconds, r.errors.rmse)).collect();
        chart
            .draw_series(LineSeries::new(points, colour.stroke_width(2)))?
            .label(m.to_string())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3)));
    }
    chart.configure_series_labels().background_style(WHITE.mix(0.85)).border_style(BLACK).draw()?;
    root.present()?;
    Ok(())
}
