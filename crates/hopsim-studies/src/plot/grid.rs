//! Rectilinear grids of cells, as maps draw them: cell edges from cell centres, the cells
//! in row-major order, and the checks and colours maps share.

use super::axis::{Axis, Scale};
use super::colour::{RGBColor, PALETTE};
use super::series::Series;
use super::DrawResult;

/// Checks that the `figure` has `len = nx × ny > 0` `cells`.
pub(super) fn check_grid(
    figure: &str,
    cells: &str,
    nx: usize,
    ny: usize,
    len: usize,
) -> DrawResult {
    if nx == 0 || ny == 0 || len != nx * ny {
        return Err(format!(
            "{figure} needs {nx}×{ny} = {} {cells}, got {len}",
            nx * ny
        ));
    }
    Ok(())
}

/// Cell edges for cell centres `centres` (ascending): midpoints, ends extended by half a gap.
fn cell_edges(centres: &[f64]) -> Vec<f64> {
    match centres.len() {
        0 => Vec::new(),
        1 => vec![centres[0] - 0.5, centres[0] + 0.5],
        n => {
            let mut edges = Vec::with_capacity(n + 1);
            edges.push(centres[0] - 0.5 * (centres[1] - centres[0]));
            for w in centres.windows(2) {
                edges.push(0.5 * (w[0] + w[1]));
            }
            edges.push(centres[n - 1] + 0.5 * (centres[n - 1] - centres[n - 2]));
            edges
        }
    }
}

fn sorted_edges(centres: &[f64]) -> (Vec<f64>, bool) {
    let ascending = centres.windows(2).all(|w| w[0] <= w[1]);
    if ascending {
        (cell_edges(centres), true)
    } else {
        let reversed: Vec<f64> = centres.iter().rev().copied().collect();
        (cell_edges(&reversed), false)
    }
}

fn cell_rect(edges: &[f64], ascending: bool, n: usize, i: usize) -> (f64, f64) {
    let k = if ascending { i } else { n - 1 - i };
    (edges[k], edges[k + 1])
}

/// The cells of a rectilinear grid with (monotonic, non-empty) cell centres `x` and `y`.
pub(super) struct CellGrid {
    x: (Vec<f64>, bool),
    y: (Vec<f64>, bool),
}

impl CellGrid {
    pub(super) fn new(x: &[f64], y: &[f64]) -> Self {
        CellGrid {
            x: sorted_edges(x),
            y: sorted_edges(y),
        }
    }

    /// The linear x and y axes over the cells.
    pub(super) fn axes(&self) -> (Axis, Axis) {
        let axis = |edges: &[f64]| Axis::new((edges[0], edges[edges.len() - 1]), Scale::Linear);
        (axis(&self.x.0), axis(&self.y.0))
    }

    /// Every cell's row-major index `iy · nx + ix` and rectangle, in that order.
    pub(super) fn cells(&self) -> impl Iterator<Item = (usize, [(f64, f64); 2])> + '_ {
        let (nx, ny) = (self.x.0.len() - 1, self.y.0.len() - 1);
        (0..ny).flat_map(move |iy| {
            (0..nx).map(move |ix| {
                let (x0, x1) = cell_rect(&self.x.0, self.x.1, nx, ix);
                let (y0, y1) = cell_rect(&self.y.0, self.y.1, ny, iy);
                (iy * nx + ix, [(x0, y0), (x1, y1)])
            })
        })
    }
}

/// The colours of overlay series: their own, else the palette from entry `first`.
pub(super) fn overlay_colors(overlays: &[Series], first: usize) -> Vec<RGBColor> {
    (overlays.iter().enumerate())
        .map(|(i, s)| s.color.unwrap_or(PALETTE[(i + first) % PALETTE.len()]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_edges_are_midpoints() {
        assert_eq!(cell_edges(&[0.0, 1.0, 3.0]), vec![-0.5, 0.5, 2.0, 4.0]);
        let (edges, up) = sorted_edges(&[3.0, 1.0, 0.0]);
        assert!(!up);
        assert_eq!(cell_rect(&edges, up, 3, 0), (2.0, 4.0));
    }
}
