//! The history a run writes, read back by column.

use std::path::Path;

pub struct History {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl History {
    pub fn read(path: &Path) -> History {
        let text = std::fs::read_to_string(path).expect("history.csv exists");
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
