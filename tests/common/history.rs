//! The history a run writes, read back by column.

use std::path::Path;

use super::gpu::family_scale;

pub struct History {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl History {
    /// The rows bit for bit, to compare two runs' histories exactly (a column an engine
    /// does not measure is NaN in both).
    pub fn bits(&self) -> Vec<Vec<u64>> {
        (self.rows.iter())
            .map(|r| r.iter().map(|x| x.to_bits()).collect())
            .collect()
    }

    pub fn read(path: &Path) -> History {
        History::parse(&std::fs::read_to_string(path).expect("history.csv exists"))
    }

    /// A history's text, as [`History::read`] reads it from its file.
    pub fn parse(text: &str) -> History {
        let mut lines = text.lines();
        let columns: Vec<String> = lines
            .next()
            .expect("header")
            .split(',')
            .map(String::from)
            .collect();
        let rows = lines
            .map(|l| {
                l.split(',')
                    .map(|v| v.parse::<f64>().expect("number"))
                    .collect()
            })
            .collect();
        History { columns, rows }
    }

    pub fn col(&self, name: &str) -> Vec<f64> {
        let i = self
            .columns
            .iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.columns));
        self.rows.iter().map(|r| r[i]).collect()
    }

    pub fn last(&self, name: &str) -> f64 {
        *self.col(name).last().expect("rows")
    }
}

/// The impulse of an explicit run's force column `f` over its rows from `from` on (at
/// times `t`): each row's force times the time its step's impulses act over
/// (`impulse_interval`): the row's own step, but for the last row the mean of its step and
/// the one before (a shortened last step's; the same where the last step is whole). So it is
/// the impulses' sum.
pub fn impulse_from(t: &[f64], f: &[f64], from: usize) -> f64 {
    (from..t.len())
        .map(|i| match i {
            i if i == from => f[i] * (t[i] - t[i - 1]),
            i if i + 1 == t.len() => f[i] * 0.5 * (t[i] - t[i - 2]),
            i => f[i] * (t[i] - t[i - 1]),
        })
        .sum()
}

/// [`impulse_from`] over every row after the first (the start).
pub fn impulse(t: &[f64], f: &[f64]) -> f64 {
    impulse_from(t, f, 1)
}

/// The mean of `y` over the rows whose `x` is within `w` of `at` (a load averaged over a
/// window of opening or travel, where an explicit run rings).
pub fn mean_near(x: &[f64], y: &[f64], at: f64, w: f64) -> f64 {
    let near: Vec<f64> = (x.iter().zip(y))
        .filter(|(x, _)| (**x - at).abs() <= w)
        .map(|(_, y)| *y)
        .collect();
    near.iter().sum::<f64>() / near.len() as f64
}

/// The largest difference between two histories' columns, relative to each column's largest
/// magnitude (columns named in `pairs`: (column of a, column of b, sign)).
pub fn history_difference(a: &History, b: &History, pairs: &[(&str, &str, f64)]) -> f64 {
    let mut worst = 0.0f64;
    for &(ca, cb, sign) in pairs {
        let (x, y) = (a.col(ca), b.col(cb));
        assert_eq!(x.len(), y.len(), "{ca}: row counts");
        // a velocity or displacement component against its body's or probe's largest
        let family = [[".vx", ".vy", ".vz"], [".ux", ".uy", ".uz"]]
            .into_iter()
            .find(|f| f.iter().any(|s| ca.ends_with(s)))
            .map_or(0.0, |f| family_scale(a, &f));
        // a penetration against the bodies' size (1 in these scenes): round-off of 1e-20
        // is no difference
        let family = if ca.ends_with(".max_penetration") {
            1.0
        } else {
            family
        };
        let scale = (x.iter().fold(family, |m, v| m.max(v.abs()))).max(1e-300);
        for (p, q) in x.iter().zip(&y) {
            worst = worst.max((p - sign * q).abs() / scale);
        }
    }
    worst
}

/// The pairs of [`history_difference`] for columns compared with their namesakes.
pub fn same_columns<'a>(columns: &[&'a str]) -> Vec<(&'a str, &'a str, f64)> {
    columns.iter().map(|c| (*c, *c, 1.0)).collect()
}
