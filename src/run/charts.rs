//! The run's charts: contact forces and energies, with the scene's exact curves.

use crate::error::Result;
use crate::model::Model;
use crate::scene::Scene;

/// Writes the run's charts into `dir`: `forces` (every interface's normal force) and
/// `energies` (kinetic, strain, total, and the friction work of interfaces with friction),
/// each with the scene's exact curves for its columns, and one chart `exact_<column>` for an
/// exact curve of any other column; and each moving rigid body's force-displacement curve
/// ([`force_displacement`]). SVG and PNG each.
pub fn write_charts(scene: &Scene, model: &Model, dir: &std::path::Path) -> Result<()> {
    use crate::output::plot::{chart, Series, Style, Table};
    let table = Table::read(&dir.join("history.csv"))?;
    let forces: Vec<String> = model
        .interfaces
        .iter()
        .map(|i| format!("{}.normal_force", i.name))
        .collect();
    let mut energies: Vec<String> = ["kinetic_energy", "strain_energy", "total_energy"]
        .map(String::from)
        .to_vec();
    energies.extend(
        model
            .interfaces
            .iter()
            .filter(|i| i.law.is_frictional())
            .map(|i| format!("{}.friction_work", i.name)),
    );
    let exact_of = |cols: &[String]| -> Vec<Series> {
        scene
            .exact
            .iter()
            .filter(|e| cols.contains(&e.column))
            .map(|e| Series {
                name: format!("{} ({})", e.column, e.label),
                x: e.points.iter().map(|p| p[0]).collect(),
                y: e.points.iter().map(|p| p[1]).collect(),
                style: Style::Exact,
                labels: Vec::new(),
            })
            .collect()
    };
    let mut charts = Vec::new();
    if !forces.is_empty() {
        charts.push(("forces".to_string(), "contact forces".to_string(), forces));
    }
    charts.push(("energies".into(), "energies".into(), energies));
    for e in &scene.exact {
        if !charts.iter().any(|(_, _, cols)| cols.contains(&e.column)) {
            let name = format!("exact_{}", e.column.replace(['.', '/'], "_"));
            charts.push((name, e.column.clone(), vec![e.column.clone()]));
        }
    }
    for (name, title, cols) in charts {
        let mut c = chart(&table, &title, &cols);
        c.series.extend(exact_of(&cols));
        c.write(dir, &name)?;
    }
    for (name, c) in force_displacement(model, &table) {
        c.write(dir, &name)?;
    }
    Ok(())
}

/// For each contact of a rigid body that moves at the start (free or prescribed, with a
/// velocity), its normal force against the body's displacement along that velocity: the
/// drop-weight test's force-displacement curve. Named `<contact>_force_displacement`.
fn force_displacement(
    model: &Model,
    table: &crate::output::plot::Table,
) -> Vec<(String, crate::output::plot::Chart)> {
    use crate::output::plot::{Chart, Series, Style};
    let mut out = Vec::new();
    for itf in &model.interfaces {
        let crate::model::Primary::Rigid { body, .. } = itf.primary else {
            continue;
        };
        let b = &model.rigid[body];
        let Some(along) = crate::material::rotation::unit(b.velocity) else {
            continue;
        };
        let u: Vec<Vec<f64>> = ["ux", "uy", "uz"]
            .iter()
            .filter_map(|c| table.col(&format!("{}.{c}", b.name)))
            .collect();
        let Some(force) = table.col(&format!("{}.normal_force", itf.name)) else {
            continue;
        };
        if u.len() < 3 {
            continue;
        }
        let x = (0..force.len())
            .map(|i| (0..3).map(|a| u[a][i] * along[a]).sum())
            .collect();
        let chart = Chart {
            title: format!("{} force against {}'s displacement", itf.name, b.name),
            x_label: format!("{} displacement along its initial velocity", b.name),
            series: vec![Series {
                name: format!("{}.normal_force", itf.name),
                x,
                y: force,
                style: Style::Line,
                labels: Vec::new(),
            }],
            log_x: false,
            log_y: false,
        };
        out.push((format!("{}_force_displacement", itf.name), chart));
    }
    out
}
