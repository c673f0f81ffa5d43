//! The tables: one per view (and mode), the same timing columns between
//! mode-specific columns on the left (what was rendered) and on the right
//! (how well the pictures agree), and the geometric means of the ratios.

use crate::measure::Timing;

/// One measured row.
pub struct Row {
    /// The row's left columns, formatted (surface and algebra, or scene,
    /// blending, level and primitives).
    pub left: String,
    /// The medians.
    pub timing: Timing,
    /// The row's right columns, formatted (agreement and more).
    pub right: String,
    /// Primitives of a generated scene (for the ≥ 1000-primitive mean).
    pub primitives: Option<usize>,
}

/// A table being printed row by row as the measurements arrive.
pub struct Table {
    rows: Vec<Row>,
    skipped: Vec<String>,
    left_width: usize,
}

impl Table {
    /// Prints the title and the column headers (`columns`: the left and
    /// right headers of the mode).
    pub fn start(title: &str, columns: (&str, &str)) -> Table {
        println!("## {title}");
        println!(
            "{} {:>11} {:>9} {:>9} {:>8} {:>8} {}",
            columns.0, "isotrace ms", "(gpu ms)", "fidget ms", "fid/iso", "fid/gpu", columns.1
        );
        Table { rows: vec![], skipped: vec![], left_width: columns.0.chars().count() }
    }

    /// Prints and keeps a row.
    pub fn add(&mut self, r: Row) {
        let t = &r.timing;
        println!(
            "{} {:>11.1} {:>9.1} {:>9.1} {:>8.2} {:>8.2} {}",
            r.left,
            t.iso_ms,
            t.iso_gpu_ms,
            t.fid_ms,
            t.fid_ms / t.iso_ms,
            t.fid_ms / t.iso_gpu_ms,
            r.right
        );
        self.rows.push(r);
    }

    /// Prints a row that could not be measured (`left`: its left columns).
    pub fn skip(&mut self, left: &str, why: &str) {
        println!("{left} {why}");
        self.skipped.push(format!("{} ({why})", left.split_whitespace().collect::<Vec<_>>().join(" ")));
    }

    /// Prints the geometric means over all rows and, when `min_primitives`
    /// is given, over the rows with at least that many primitives.
    pub fn finish(self, min_primitives: Option<usize>) {
        if !self.rows.is_empty() {
            self.means("geomean", &self.rows.iter().collect::<Vec<_>>());
        }
        if let Some(n) = min_primitives {
            let big: Vec<&Row> = self.rows.iter().filter(|r| r.primitives.is_some_and(|p| p >= n)).collect();
            if !big.is_empty() {
                self.means(&format!(">= {n} prims"), &big);
            }
        }
        if !self.skipped.is_empty() {
            println!("# skipped: {}", self.skipped.join(", "));
        }
        println!();
    }

    fn means(&self, label: &str, rows: &[&Row]) {
        let geo = |f: &dyn Fn(&Timing) -> f64| (rows.iter().map(|r| f(&r.timing).ln()).sum::<f64>() / rows.len() as f64).exp();
        let g = geo(&|t| t.fid_ms / t.iso_ms);
        let gg = geo(&|t| t.fid_ms / t.iso_gpu_ms);
        println!(
            "{label:<w$} {:>11.1} {:>9.1} {:>9.1} {:>8.2} {:>8.2}",
            geo(&|t| t.iso_ms),
            geo(&|t| t.iso_gpu_ms),
            geo(&|t| t.fid_ms),
            g,
            gg,
            w = self.left_width
        );
        let verdict = |g: f64| if g >= 1.0 { format!("isotrace {g:.2}x faster") } else { format!("fidget {:.2}x faster", 1.0 / g) };
        println!("# {label}: geometric mean of fidget/isotrace over {} rows: {g:.2} by wall time ({}),", rows.len(), verdict(g));
        println!("#   {gg:.2} against isotrace's kernel time alone ({})", verdict(gg));
    }
}
