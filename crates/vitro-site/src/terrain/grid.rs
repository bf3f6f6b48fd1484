//! A georeferenced raster and its ESRI ASCII grid form.
//!
//! Values sit at cell centres; `NaN` marks no-data. Rows are stored south to north.

use super::TerrainError;
use std::fmt::Write as _;

/// A raster of `f64` values on square cells, georeferenced by its lower-left corner.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Number of columns (west to east).
    pub ncols: usize,
    /// Number of rows (south to north).
    pub nrows: usize,
    /// Cell size, metres.
    pub cellsize: f64,
    /// Georeferenced coordinate (e.g. UTM easting, northing) of the lower-left cell corner.
    pub origin: [f64; 2],
    /// Values, row-major, row 0 southernmost; `NaN` is no-data.
    pub values: Vec<f64>,
}

impl Grid {
    /// A grid filled with `value`.
    pub fn filled(ncols: usize, nrows: usize, cellsize: f64, origin: [f64; 2], value: f64) -> Self {
        Grid {
            ncols,
            nrows,
            cellsize,
            origin,
            values: vec![value; ncols * nrows],
        }
    }
    /// The value at column `col`, row `row` (row 0 south); `None` out of range or no-data.
    pub fn get(&self, col: usize, row: usize) -> Option<f64> {
        if col >= self.ncols || row >= self.nrows {
            return None;
        }
        let v = self.values[row * self.ncols + col];
        (!v.is_nan()).then_some(v)
    }
    /// Sets the value at (`col`, `row`); ignored out of range.
    pub fn set(&mut self, col: usize, row: usize, v: f64) {
        if col < self.ncols && row < self.nrows {
            self.values[row * self.ncols + col] = v;
        }
    }
    /// Local coordinate (metres from the lower-left corner) of the centre of a cell.
    pub fn cell_centre(&self, col: usize, row: usize) -> [f64; 2] {
        [
            (col as f64 + 0.5) * self.cellsize,
            (row as f64 + 0.5) * self.cellsize,
        ]
    }
    /// Georeferenced coordinate to local metres.
    pub fn to_local(&self, geo: [f64; 2]) -> [f64; 2] {
        [geo[0] - self.origin[0], geo[1] - self.origin[1]]
    }
    /// Local metres to georeferenced coordinate.
    pub fn to_geo(&self, local: [f64; 2]) -> [f64; 2] {
        [local[0] + self.origin[0], local[1] + self.origin[1]]
    }
    /// Width and height of the grid, metres.
    pub fn size(&self) -> [f64; 2] {
        [
            self.ncols as f64 * self.cellsize,
            self.nrows as f64 * self.cellsize,
        ]
    }
    /// Smallest and largest value (no-data skipped); `None` if all are no-data.
    pub fn range(&self) -> Option<[f64; 2]> {
        let mut it = self.values.iter().copied().filter(|v| !v.is_nan());
        let first = it.next()?;
        Some(it.fold([first, first], |[lo, hi], v| [lo.min(v), hi.max(v)]))
    }

    /// Parses an ESRI ASCII grid (`ncols`, `nrows`, `xllcorner|xllcenter`,
    /// `yllcorner|yllcenter`, `cellsize`, optional `NODATA_value`, then `nrows` rows of values,
    /// northernmost first). Errors name the line and column (1-based).
    ///
    /// ```
    /// use vitro_site::terrain::Grid;
    /// let g = Grid::parse_asc("ncols 2\nnrows 2\nxllcorner 10\nyllcorner 20\ncellsize 5\n\
    ///     NODATA_value -9999\n1 2\n3 -9999\n").unwrap();
    /// assert_eq!((g.get(0, 1), g.get(0, 0), g.get(1, 0)), (Some(1.0), Some(3.0), None));
    /// let err = Grid::parse_asc("ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 x\n");
    /// assert_eq!(err.unwrap_err().to_string(), "line 6, column 3: bad value \"x\"");
    /// ```
    pub fn parse_asc(text: &str) -> Result<Self, TerrainError> {
        let mut tokens = text.lines().enumerate().flat_map(|(l, line)| {
            let mut out = Vec::new();
            let mut start = None;
            for (c, ch) in line
                .char_indices()
                .chain(std::iter::once((line.len(), ' ')))
            {
                match (ch.is_whitespace(), start) {
                    (false, None) => start = Some(c),
                    (true, Some(s)) => {
                        out.push((l + 1, line[..s].chars().count() + 1, &line[s..c]));
                        start = None;
                    }
                    _ => {}
                }
            }
            out
        });
        let at = |line, column, what: String| TerrainError::Parse { line, column, what };
        let mut header: [Option<f64>; 6] = [None; 6];
        let mut centre = [false; 2];
        let names = ["ncols", "nrows", "xll", "yll", "cellsize", "nodata_value"];
        let first_value = loop {
            let Some((line, col, tok)) = tokens.next() else {
                return Err(TerrainError::Missing("grid values".into()));
            };
            let key = tok.to_ascii_lowercase();
            if key.starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+' || c == '.') {
                break (line, col, tok);
            }
            let slot = match key.as_str() {
                "ncols" => 0,
                "nrows" => 1,
                "xllcorner" | "xllcenter" => 2,
                "yllcorner" | "yllcenter" => 3,
                "cellsize" => 4,
                "nodata_value" => 5,
                _ => return Err(at(line, col, format!("unknown header key {tok:?}"))),
            };
            if slot == 2 || slot == 3 {
                centre[slot - 2] = key.ends_with("center");
            }
            let (vl, vc, vt) = tokens
                .next()
                .ok_or_else(|| at(line, col, format!("header {tok} has no value")))?;
            if vl != line {
                return Err(at(line, col, format!("header {tok} has no value")));
            }
            let v: f64 = vt
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(|| at(vl, vc, format!("bad value {vt:?} for {tok}")))?;
            header[slot] = Some(v);
        };
        let need = |i: usize| header[i].ok_or_else(|| TerrainError::Missing(names[i].into()));
        let dim = |i: usize| -> Result<usize, TerrainError> {
            let v = need(i)?;
            if v >= 1.0 && v.fract() == 0.0 && v <= u32::MAX as f64 {
                Ok(v as usize)
            } else {
                Err(TerrainError::Invalid(format!(
                    "{} must be a positive integer, got {v}",
                    names[i]
                )))
            }
        };
        let (ncols, nrows) = (dim(0)?, dim(1)?);
        let cellsize = need(4)?;
        if cellsize <= 0.0 {
            return Err(TerrainError::Invalid(format!(
                "cellsize must be positive, got {cellsize}"
            )));
        }
        let half = |c: bool| if c { cellsize / 2.0 } else { 0.0 };
        let origin = [need(2)? - half(centre[0]), need(3)? - half(centre[1])];
        let nodata = header[5];
        // Each value takes at least one character of the text: a header that announces more
        // cells than the text can hold is refused before the grid is allocated.
        let total = ncols
            .checked_mul(nrows)
            .filter(|&n| n <= text.len())
            .ok_or_else(|| {
                TerrainError::Invalid(format!(
                    "{ncols} x {nrows} cells announced, more than the {} characters of the \
                     file can hold",
                    text.len()
                ))
            })?;
        let mut values = vec![f64::NAN; total];
        let mut k = 0;
        for (line, col, tok) in std::iter::once(first_value).chain(tokens) {
            if k == total {
                return Err(at(line, col, format!("more than {total} values")));
            }
            let v: f64 = tok
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(|| at(line, col, format!("bad value {tok:?}")))?;
            let (row_from_top, c) = (k / ncols, k % ncols);
            if Some(v) != nodata {
                values[(nrows - 1 - row_from_top) * ncols + c] = v;
            }
            k += 1;
        }
        if k < total {
            return Err(TerrainError::Missing(format!(
                "values: expected {total} ({ncols} x {nrows}), found {k}"
            )));
        }
        Ok(Grid {
            ncols,
            nrows,
            cellsize,
            origin,
            values,
        })
    }

    /// Writes the grid as an ESRI ASCII grid (`xllcorner`/`yllcorner`, no-data as -9999).
    /// Whole numbers are written without a decimal point.
    pub fn to_asc(&self) -> String {
        let mut s = String::with_capacity(self.values.len() * 4 + 200);
        let _ = writeln!(s, "ncols        {}", self.ncols);
        let _ = writeln!(s, "nrows        {}", self.nrows);
        let _ = writeln!(s, "xllcorner    {}", self.origin[0]);
        let _ = writeln!(s, "yllcorner    {}", self.origin[1]);
        let _ = writeln!(s, "cellsize     {}", self.cellsize);
        let _ = writeln!(s, "NODATA_value -9999");
        for row in (0..self.nrows).rev() {
            for col in 0..self.ncols {
                if col > 0 {
                    s.push(' ');
                }
                match self.get(col, row) {
                    Some(v) => {
                        let _ = write!(s, "{v}");
                    }
                    None => s.push_str("-9999"),
                }
            }
            s.push('\n');
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_centre_header() {
        let text = "NCOLS 3\nnrows 2\nxllcenter 5\nyllcenter 5\ncellsize 10\n1 2 3\n4 5.5 6\n";
        let g = Grid::parse_asc(text).unwrap();
        assert_eq!(g.origin, [0.0, 0.0]);
        assert_eq!(g.get(1, 0), Some(5.5));
        assert_eq!(g.get(2, 1), Some(3.0));
        let again = Grid::parse_asc(&g.to_asc()).unwrap();
        assert_eq!(again, g);
    }

    #[test]
    fn errors_name_line_and_column() {
        let h = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
        let e = |t: &str| Grid::parse_asc(t).unwrap_err().to_string();
        assert_eq!(
            e(&format!("{h}1 2\n3\n")),
            "missing values: expected 4 (2 x 2), found 3"
        );
        assert_eq!(
            e(&format!("{h}1 2\n3 4 5\n")),
            "line 7, column 5: more than 4 values"
        );
        assert_eq!(
            e(&format!("{h}1 2\n  3 nan\n")),
            "line 7, column 5: bad value \"nan\""
        );
        assert_eq!(
            e("ncols 2\nrows 2\n"),
            "line 2, column 1: unknown header key \"rows\""
        );
        assert_eq!(e("ncols 2\nnrows 2\ncellsize 1\n1 2 3 4"), "missing xll");
        assert_eq!(
            e("ncols 0\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1"),
            "invalid grid: ncols must be a positive integer, got 0"
        );
    }
}
