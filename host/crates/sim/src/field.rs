//! The height field: one Z per XY cell of the stock, stored in square tiles so
//! that threads can cut different tiles at once, with the highest cell of
//! every block and tile beside it so that a cut can pass over material it
//! cannot reach.

use std::collections::TryReserveError;

use super::Stock;

/// Cells along a tile's side.
pub const TILE: usize = 64;
/// Cells along a block's side: a tile is BLOCKS x BLOCKS blocks.
pub const BLOCK: usize = 8;
/// Blocks in a tile.
pub const BLOCKS: usize = (TILE / BLOCK) * (TILE / BLOCK);

#[derive(Clone, Debug)]
pub struct HeightField {
    pub stock: Stock,
    /// Cells along X and Y.
    pub nx: usize,
    pub ny: usize,
    /// A cell's side, in machine units.
    pub cell: f64,
    pub tiles_x: usize,
    pub tiles_y: usize,
    /// Tile-major: tile (tx, ty) holds TILE x TILE cells, row-major inside.
    pub(super) data: Vec<f32>,
    /// Per tile, row-major: the highest cell of each block (minus infinity
    /// for a block wholly outside the stock). Exact after every cut.
    pub(super) block_tops: Vec<f32>,
    /// The highest cell of each tile: the highest of its blocks.
    pub(super) tile_tops: Vec<f32>,
}

impl HeightField {
    /// The bytes a field of `cell` over `stock` takes.
    pub fn bytes(stock: &Stock, cell: f64) -> u128 {
        let (nx, ny) = Self::cells(stock, cell);
        let tiles = nx.div_ceil(TILE) as u128 * ny.div_ceil(TILE) as u128;
        tiles * (TILE * TILE + BLOCKS + 1) as u128 * 4
    }

    pub fn cells(stock: &Stock, cell: f64) -> (usize, usize) {
        let count = |len: f64| (len / cell).round().clamp(2.0, 1e12) as usize;
        (count(stock.max[0] - stock.min[0]), count(stock.max[1] - stock.min[1]))
    }

    /// Uncut stock. The caller has checked the size against the memory limit;
    /// the system may still not have that much memory to give.
    pub fn new(stock: Stock, cell: f64) -> Result<HeightField, TryReserveError> {
        let (nx, ny) = Self::cells(&stock, cell);
        // Cells tile the stock exactly: stretch the cell a little if the size is not a multiple.
        let cell = (stock.max[0] - stock.min[0]) / nx as f64;
        let (tiles_x, tiles_y) = (nx.div_ceil(TILE), ny.div_ceil(TILE));
        let top = stock.max[2] as f32;
        let count = tiles_x * tiles_y * TILE * TILE;
        let mut data = Vec::new();
        data.try_reserve_exact(count)?;
        data.resize(count, top);
        let side = TILE / BLOCK;
        let mut block_tops = Vec::new();
        block_tops.try_reserve_exact(tiles_x * tiles_y * BLOCKS)?;
        for t in 0..tiles_x * tiles_y {
            let (i_base, j_base) = ((t % tiles_x) * TILE, (t / tiles_x) * TILE);
            for b in 0..BLOCKS {
                let inside = i_base + (b % side) * BLOCK < nx && j_base + (b / side) * BLOCK < ny;
                block_tops.push(if inside { top } else { f32::NEG_INFINITY });
            }
        }
        let tile_tops = vec![top; tiles_x * tiles_y];
        Ok(HeightField { stock, nx, ny, cell, tiles_x, tiles_y, data, block_tops, tile_tops })
    }

    /// Lowers each cell to `heights` (row-major, `j * nx + i`; `None`: no
    /// material there, down to the bottom), never raising one: a stock that
    /// starts as a casting or an earlier job's part.
    pub fn carve(&mut self, heights: &[Option<f64>]) {
        let bottom = self.bottom() as f32;
        for j in 0..self.ny {
            for i in 0..self.nx {
                let k = self.index(i, j);
                let z = heights[j * self.nx + i].map_or(bottom, |z| (z as f32).max(bottom));
                self.data[k] = self.data[k].min(z);
            }
        }
        // The highest cell of every block and tile, again.
        let side = TILE / BLOCK;
        for t in 0..self.tiles_x * self.tiles_y {
            let (i_base, j_base) = ((t % self.tiles_x) * TILE, (t / self.tiles_x) * TILE);
            for b in 0..BLOCKS {
                let (i0, j0) = (i_base + (b % side) * BLOCK, j_base + (b / side) * BLOCK);
                let mut highest = f32::NEG_INFINITY;
                for j in j0..(j0 + BLOCK).min(self.ny) {
                    for i in i0..(i0 + BLOCK).min(self.nx) {
                        highest = highest.max(self.data[self.index(i, j)]);
                    }
                }
                self.block_tops[t * BLOCKS + b] = highest;
            }
            self.tile_tops[t] =
                self.block_tops[t * BLOCKS..][..BLOCKS].iter().copied().fold(f32::NEG_INFINITY, f32::max);
        }
    }

    /// A cell's side along Y (equal to `cell` unless the stock's Y is not a multiple of it).
    pub fn cell_y(&self) -> f64 {
        (self.stock.max[1] - self.stock.min[1]) / self.ny as f64
    }

    #[inline]
    pub(super) fn index(&self, i: usize, j: usize) -> usize {
        let (ti, tj) = (i / TILE, j / TILE);
        (tj * self.tiles_x + ti) * TILE * TILE + (j % TILE) * TILE + i % TILE
    }

    /// The height of cell (i, j): i along X, j along Y, from the stock's lower-left corner.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.data[self.index(i, j)] as f64
    }

    /// The XY centre of cell (i, j).
    #[inline]
    pub fn centre(&self, i: usize, j: usize) -> [f64; 2] {
        [self.stock.min[0] + (i as f64 + 0.5) * self.cell, self.stock.min[1] + (j as f64 + 0.5) * self.cell_y()]
    }

    pub fn top(&self) -> f64 {
        self.stock.max[2]
    }

    pub fn bottom(&self) -> f64 {
        self.stock.min[2]
    }

    /// The volume removed from the stock.
    pub fn removed_volume(&self) -> f64 {
        let top = self.top();
        let mut sum = 0.0;
        for j in 0..self.ny {
            for i in 0..self.nx {
                sum += top - self.get(i, j);
            }
        }
        sum * self.cell * self.cell_y()
    }

    /// The deepest cell's height (the top when nothing was cut).
    pub fn lowest(&self) -> f64 {
        let mut low = self.top();
        for j in 0..self.ny {
            for i in 0..self.nx {
                low = low.min(self.get(i, j));
            }
        }
        low
    }
}
