//! The centred-exponential evaluation of the cross products, by prefix tables instead of merges.
//!
//! With `c₀` the middle of the spike-time span, every spike stores `e⁻ = e^{−(t − c₀)/τ}` and
//! `e⁺ = e^{(t − c₀)/τ}`, and for samples `a` (row) and `b` (column)
//!
//! ```text
//! ⟨a, b⟩ = Σ_{j ∈ b} e⁻_j · P_a(≤ t_j)  +  Σ_{k ∈ a} e⁻_k · P_b(< t_k),   P_a(≤ t) = Σ_{l ∈ a, t_l ≤ t} e⁺_l
//! ```
//!
//! (every pair counted once, coincident pairs in the first sum with weight `e⁻·e⁺ = 1`). A merge
//! finds `P_a(≤ t_j)` by walking both trains, one dependent step per spike. Here the row sample's
//! prefix `P` is tabulated once over a grid of **global rank cells** (the rank of a time among
//! all distinct spike times of the prepared samples, shifted right by a fixed amount), so each
//! column spike finds its prefix with one table read: the cell's prefix before its first spike,
//! or after it when that spike's rank is not larger. Cells holding two or more spikes of the row
//! sample (rare: the grid has several cells per spike) continue in a short overflow list. Column
//! spikes are independent of each other, so the loop runs at the machine's load throughput
//! instead of a merge's latency; the prefixes read are exactly the merge's (the same running
//! sums), only the order of the final additions differs.
//!
//! The labelled-line tables are the same per channel, laid out time cell-major
//! (`cell · P + channel`) so that a column sample's spikes, visited in time order, read both
//! tables forwards. A row computes `Σ_{j ∈ b} e⁻_j P_a(≤ t_j)` for the columns after it and the
//! strict `Σ_{j ∈ b} e⁻_j P_a(< t_j)` for the columns before it; `⟨a, b⟩` is the sum of the two
//! entries, so every ordered pair is one pass over the column's spikes. Rows are tabulated
//! [`LANES`] at a time, lane by lane in each cell, so one column spike reads the prefixes of
//! all of them with one compare, one select and one multiply-add per lane, vectorised; each lane
//! does exactly what its row alone would. A single pair, where tabulating would cost more than
//! it saves, finds the same prefixes by walking the row's trains alongside the column's spikes
//! (the same sums in the same order: the same bits).

use rayon::prelude::*;
use std::cmp::Ordering;
use std::ops::Range;

/// Largest `span/(2τ)` for which the centred-exponential evaluation is used
/// ([module docs](super)).
pub const CENTRED_EXP_LIMIT: f64 = 690.0;

/// Target number of table cells per spike of a mean sample (pooled) or channel (labelled): the
/// grid is the next power of two at or above, so cells hold at most one spike of a row sample
/// with high probability. Spikes cluster in time (a slide's phases), so a probe often lands
/// near a row spike: 8 cells per spike keeps the overflow walks rare (under 1 % of the lookups
/// of a block of rows on the artificial set) while the tables stay small (4 and 16 cost 5–15 %
/// more CPU time there). The grid never changes a sum, only where its prefixes are read from.
const CELLS_PER_SPIKE: f64 = 8.0;

/// Rank of "no spike" in a cell (larger than every spike's rank).
const NO_SPIKE: u32 = u32::MAX;

/// Spike ranks → table cells, shared by every prepared sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Grid {
    channels: usize,
    pooled_shift: u32,
    pooled_cells: usize,
    labelled_shift: u32,
    labelled_time_cells: usize,
}

impl Grid {
    /// A grid for `distinct` ranks, `channels` channels and `mean_spikes` spikes per sample;
    /// `None` when ranks or labelled cells would not fit the `u32` fields.
    pub(super) fn new(distinct: usize, channels: usize, mean_spikes: f64) -> Option<Self> {
        let shift = |spikes_per_train: f64| -> u32 {
            let width = distinct as f64 / (CELLS_PER_SPIKE * spikes_per_train.max(1e-300));
            if width >= 2.0 {
                width.log2().floor().min(31.0) as u32
            } else {
                0
            }
        };
        let cells = |shift: u32| (distinct.saturating_sub(1) >> shift) + 1;
        let pooled_shift = shift(mean_spikes);
        let labelled_shift = shift(mean_spikes / channels.max(1) as f64);
        let grid = Self {
            channels,
            pooled_shift,
            pooled_cells: cells(pooled_shift),
            labelled_shift,
            labelled_time_cells: cells(labelled_shift),
        };
        let fits = distinct < NO_SPIKE as usize
            && grid.labelled_time_cells.checked_mul(channels.max(1))? <= u32::MAX as usize;
        fits.then_some(grid)
    }

    #[inline(always)]
    fn pooled_cell(&self, rank: u32) -> usize {
        (rank >> self.pooled_shift) as usize
    }

    #[inline(always)]
    fn labelled_cell(&self, rank: u32, channel: usize) -> usize {
        (rank >> self.labelled_shift) as usize * self.channels + channel
    }

    /// The channel of a probe (its labelled cell without the time cell).
    #[inline(always)]
    fn channel(&self, p: &Probe) -> usize {
        p.labelled_cell as usize - self.labelled_cell(p.rank, 0)
    }

    /// Number of channels.
    pub(super) fn channels(&self) -> usize {
        self.channels
    }
}

/// One spike of a column sample: what a lookup in a row sample's tables needs.
#[derive(Debug, Clone, Copy)]
struct Probe {
    /// Global rank of the spike time.
    rank: u32,
    /// Its labelled-line cell ([`Grid::labelled_cell`]).
    labelled_cell: u32,
    /// `e^{−(t − c₀)/τ}`.
    e_minus: f64,
}

/// One sample prepared for the centred evaluation.
#[derive(Debug, Clone)]
pub(super) struct CentredSample {
    /// Spikes in time order (ties by channel), as probes of other samples' tables.
    probes: Vec<Probe>,
    /// `(rank, e⁺)` per spike, channel-major (each channel in time order); `offsets` as the CSR.
    labelled: Vec<(u32, f64)>,
    offsets: Vec<usize>,
    /// `(rank, e⁺)` per spike in time order.
    pooled: Vec<(u32, f64)>,
    /// `Σ_n ⟨u_n, u_n⟩` and `⟨∪u, ∪u⟩`.
    pub(super) labelled_self: f64,
    pub(super) pooled_self: f64,
}

/// `n + 2·Σ_k e⁻_k·P(< k)` over one train in merge order (`P` the running sum of `e⁺`).
fn self_product(train: impl Iterator<Item = (f64, f64)>) -> f64 {
    let (mut n, mut prefix, mut markage_sum) = (0.0, 0.0, 0.0);
    for (e_minus, e_plus) in train {
        markage_sum += e_minus * prefix;
        prefix += e_plus;
        n += 1.0;
    }
    n + 2.0 * markage_sum
}

impl CentredSample {
    /// From the spikes `(channel, time)` in time order (ties by channel) and their global
    /// ranks (the grid's).
    pub(super) fn new(
        spikes: &[(u32, f64)],
        ranks: &[u64],
        channels: usize,
        grid: &Grid,
        centre: f64,
        inv_tau: f64,
    ) -> Self {
        let ranks: Vec<u32> = ranks
            .iter()
            .map(|&r| u32::try_from(r).expect("the grid admits every rank"))
            .collect();
        let exps: Vec<(f64, f64)> = spikes
            .iter()
            .map(|&(_, t)| {
                let x = (t - centre) * inv_tau;
                ((-x).exp(), x.exp())
            })
            .collect();
        let probes = spikes
            .iter()
            .zip(&ranks)
            .zip(&exps)
            .map(|((&(c, _), &rank), &(e_minus, _))| Probe {
                rank,
                labelled_cell: grid.labelled_cell(rank, c as usize) as u32,
                e_minus,
            })
            .collect();
        let pooled: Vec<(u32, f64)> = ranks
            .iter()
            .zip(&exps)
            .map(|(&r, &(_, e))| (r, e))
            .collect();
        // Channel-major, each channel in time order (a stable sort of the time-ordered list).
        let mut order: Vec<usize> = (0..spikes.len()).collect();
        order.sort_by_key(|&k| spikes[k].0);
        let mut offsets = vec![0; channels + 1];
        for &(c, _) in spikes {
            offsets[c as usize + 1] += 1;
        }
        for c in 0..channels {
            offsets[c + 1] += offsets[c];
        }
        let labelled_self = (0..channels)
            .map(|c| self_product(order[offsets[c]..offsets[c + 1]].iter().map(|&k| exps[k])))
            .sum();
        Self {
            probes,
            labelled: order.iter().map(|&k| pooled[k]).collect(),
            offsets,
            pooled_self: self_product(exps.iter().copied()),
            pooled,
            labelled_self,
        }
    }

    /// The spikes in time order (ties by channel) as `(channel, rank, e⁻, e⁺)`.
    pub(super) fn spikes<'a>(
        &'a self,
        grid: &'a Grid,
    ) -> impl ExactSizeIterator<Item = (usize, u32, f64, f64)> + 'a {
        let spikes = self.probes.iter().zip(&self.pooled);
        spikes.map(|(p, &(_, e_plus))| (grid.channel(p), p.rank, p.e_minus, e_plus))
    }
}

/// Row samples tabulated together: one per lane of a [`LaneTable`] cell, so that each column
/// probe reads the prefixes of all of them at once (one vector compare, select and
/// multiply-add per lane group instead of one scalar lookup per row). 8 lanes take 0.55–0.6×
/// the CPU time of one row at a time on the artificial set, 4 lanes 0.65×.
const LANES: usize = 8;

/// The prefixes of the [`LANES`] rows of a block in one cell (lane `l` for row `l`): before the
/// cell's first spike of that row, and after it.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(64))]
struct LaneValues {
    before: [f64; LANES],
    after_first: [f64; LANES],
}

/// One kind of table (labelled line or pooled) of a block of rows, in cells of [`LANES`] lanes.
#[derive(Debug, Clone, Default)]
struct LaneTable {
    values: Vec<LaneValues>,
    /// Rank of each lane's first spike in the cell; [`NO_SPIKE`] when it has none.
    first_rank: Vec<[u32; LANES]>,
    /// Bit `l` set when lane `l` has two or more spikes in the cell.
    overflowing: Vec<u8>,
    /// Where the run of [`BlockTables::overflow`] holding the cell's second and later spikes
    /// starts, per lane; set (and read) only where the lane's bit of `overflowing` is.
    overflow_start: Vec<[u32; LANES]>,
}

const _: () = assert!(LANES <= u8::BITS as usize, "one overflow bit per lane");

/// The prefix tables `P(≤ t)` of a block of up to [`LANES`] row samples on the grid, labelled
/// line and pooled.
#[derive(Debug, Clone, Default)]
pub(super) struct BlockTables {
    labelled: LaneTable,
    pooled: LaneTable,
    /// Runs of `(rank, prefix after the spike)` for the second and later spikes of a cell, each
    /// run ended by `(NO_SPIKE, _)`.
    overflow: Vec<(u32, f64)>,
}

impl LaneTable {
    /// `cells` empty cells (reusing the allocations).
    fn reset(&mut self, cells: usize) {
        // `fill_lane` writes every cell's values in its lane, and the lanes a block that is not
        // full leaves unfilled are never read back: the values need no clearing.
        self.values.resize(cells, LaneValues::default());
        self.first_rank.clear();
        self.first_rank.resize(cells, [NO_SPIKE; LANES]);
        self.overflowing.clear();
        self.overflowing.resize(cells, 0);
        // Read only where `overflowing` says it was set: no need to clear it.
        self.overflow_start.resize(cells, [0; LANES]);
    }

    /// Fills lane `lane` of the cells `first + g·stride` (`g` the time cell) with the prefixes
    /// of one train `(rank, e⁺)` in time order; the cells' other lanes are left as they are.
    fn fill_lane(
        &mut self,
        overflow: &mut Vec<(u32, f64)>,
        lane: usize,
        train: &[(u32, f64)],
        shift: u32,
        first: usize,
        stride: usize,
    ) {
        let mut prefix = 0.0;
        let mut spikes = train.iter().peekable();
        let cells = (first..self.values.len()).step_by(stride);
        for (g, cell) in cells.enumerate() {
            let before = prefix;
            let values = &mut self.values[cell];
            values.before[lane] = before;
            let Some(&(first_rank, e_plus)) = spikes.next_if(|&&(r, _)| (r >> shift) as usize == g)
            else {
                values.after_first[lane] = before;
                continue;
            };
            prefix += e_plus;
            values.after_first[lane] = prefix;
            self.first_rank[cell][lane] = first_rank;
            let start = overflow.len();
            while let Some(&(r, e_plus)) = spikes.next_if(|&&(r, _)| (r >> shift) as usize == g) {
                prefix += e_plus;
                overflow.push((r, prefix));
            }
            if overflow.len() > start {
                overflow.push((NO_SPIKE, prefix));
                self.overflowing[cell] |= 1 << lane;
                self.overflow_start[cell][lane] = start as u32;
            }
        }
    }

    /// `P(≤ rank)` (or `P(< rank)` when `STRICT`) of every lane from cell `cell`.
    #[inline(always)]
    fn prefixes<const STRICT: bool>(
        &self,
        cell: usize,
        rank: u32,
        overflow: &[(u32, f64)],
    ) -> [f64; LANES] {
        let LaneValues {
            before,
            after_first,
        } = self.values[cell];
        let first_rank = self.first_rank[cell];
        let mut p = [0.0; LANES];
        for l in 0..LANES {
            let counted = if STRICT {
                first_rank[l] < rank
            } else {
                first_rank[l] <= rank
            };
            // A blend of the two whole rows (a branch or a select of addresses per lane would
            // not vectorise).
            let take = (counted as u64).wrapping_neg();
            p[l] =
                f64::from_bits((after_first[l].to_bits() & take) | (before[l].to_bits() & !take));
        }
        match self.overflowing[cell] {
            0 => p,
            overflowing => {
                self.continue_overflowing::<STRICT>(cell, overflowing, rank, overflow, p)
            }
        }
    }

    /// Continues the prefixes of the lanes set in `overflowing` over their cell's second and
    /// later spikes.
    #[cold]
    #[inline(never)]
    fn continue_overflowing<const STRICT: bool>(
        &self,
        cell: usize,
        overflowing: u8,
        rank: u32,
        overflow: &[(u32, f64)],
        mut p: [f64; LANES],
    ) -> [f64; LANES] {
        for (l, &start) in self.overflow_start[cell].iter().enumerate() {
            if overflowing & (1 << l) == 0 {
                continue;
            }
            for &(r, after) in &overflow[start as usize..] {
                let counted = if STRICT { r < rank } else { r <= rank };
                if !counted {
                    break;
                }
                p[l] = after;
            }
        }
        p
    }
}

impl BlockTables {
    /// Tabulates `rows` (at most [`LANES`]) in lanes `0..rows.len()`; the other lanes are empty.
    pub(super) fn fill(&mut self, rows: &[CentredSample], grid: &Grid) {
        self.overflow.clear();
        self.pooled.reset(grid.pooled_cells);
        self.labelled
            .reset(grid.labelled_time_cells * grid.channels);
        for (lane, sample) in rows.iter().enumerate() {
            self.pooled.fill_lane(
                &mut self.overflow,
                lane,
                &sample.pooled,
                grid.pooled_shift,
                0,
                1,
            );
            for (c, w) in sample.offsets.windows(2).enumerate() {
                self.labelled.fill_lane(
                    &mut self.overflow,
                    lane,
                    &sample.labelled[w[0]..w[1]],
                    grid.labelled_shift,
                    c,
                    grid.channels,
                );
            }
        }
    }
}

/// Probes handled per step of [`lane_half_products`] (independent accumulator chains).
const UNROLL: usize = 4;

/// `Σ_{j ∈ b} e⁻_j·P(t_j)` over the column `b` for every lane of `table` (the pooled one when
/// `POOLED`, else the labelled-line one), with `P(≤ t)` or, when `STRICT`, `P(< t)`: probe `j`
/// adds to chain `j mod UNROLL` of each lane, and the chains are summed as
/// `(c₀ + c₁) + (c₂ + c₃)`, so every lane is the same sequence of operations as one row alone.
fn lane_half_products<const STRICT: bool, const POOLED: bool>(
    table: &LaneTable,
    overflow: &[(u32, f64)],
    column: &CentredSample,
    grid: &Grid,
) -> [f64; LANES] {
    let mut acc = [[0.0f64; LANES]; UNROLL];
    let chunks = column.probes.chunks_exact(UNROLL);
    let rest = chunks.remainder();
    for chunk in chunks {
        // Constant chain indices, so the accumulators stay in registers.
        lane_probe::<STRICT, POOLED>(table, overflow, &chunk[0], grid, &mut acc[0]);
        lane_probe::<STRICT, POOLED>(table, overflow, &chunk[1], grid, &mut acc[1]);
        lane_probe::<STRICT, POOLED>(table, overflow, &chunk[2], grid, &mut acc[2]);
        lane_probe::<STRICT, POOLED>(table, overflow, &chunk[3], grid, &mut acc[3]);
    }
    for (k, p) in rest.iter().enumerate() {
        lane_probe::<STRICT, POOLED>(table, overflow, p, grid, &mut acc[k]);
    }
    std::array::from_fn(|l| (acc[0][l] + acc[1][l]) + (acc[2][l] + acc[3][l]))
}

/// One probe of [`lane_half_products`] into one accumulator chain of every lane.
#[inline(always)]
fn lane_probe<const STRICT: bool, const POOLED: bool>(
    table: &LaneTable,
    overflow: &[(u32, f64)],
    p: &Probe,
    grid: &Grid,
    chain: &mut [f64; LANES],
) {
    let cell = if POOLED {
        grid.pooled_cell(p.rank)
    } else {
        p.labelled_cell as usize
    };
    let prefixes = table.prefixes::<STRICT>(cell, p.rank, overflow);
    for l in 0..LANES {
        chain[l] = p.e_minus.mul_add(prefixes[l], chain[l]);
    }
}

/// `Σ_n ⟨u_n, v_n⟩` and `⟨∪u, ∪v⟩` between two samples, as the sum of the two entries of
/// [`half_product_rows`], bit for bit, without tabulating either sample.
pub(super) fn cross_pair(a: &CentredSample, b: &CentredSample, grid: &Grid) -> (f64, f64) {
    let (ll_ab, sp_ab) = merged_half_products::<false>(a, b, grid);
    let (ll_ba, sp_ba) = merged_half_products::<true>(b, a, grid);
    (ll_ab + ll_ba, sp_ab + sp_ba)
}

/// [`lane_half_products`] of the row sample `row` over `column` (both tables), with each prefix found by walking
/// `row`'s trains alongside the column's spikes instead of reading a table: the same running
/// sums, accumulated in the same chains, so the same result bit for bit, in O(n + m) without
/// the O(cells) tabulation (for single pairs).
fn merged_half_products<const STRICT: bool>(
    row: &CentredSample,
    column: &CentredSample,
    grid: &Grid,
) -> (f64, f64) {
    let counts = |r: u32, rank: u32| if STRICT { r < rank } else { r <= rank };
    let (mut ll, mut sp) = ([0.0f64; UNROLL], [0.0f64; UNROLL]);
    // Per channel: the next spike of `row` and the prefix before it; the same for the pool.
    let mut next: Vec<usize> = row.offsets[..row.offsets.len() - 1].to_vec();
    let mut channel_prefix = vec![0.0f64; next.len()];
    let (mut next_pooled, mut pooled_prefix) = (0, 0.0f64);
    for (j, p) in column.probes.iter().enumerate() {
        let channel = grid.channel(p);
        let end = row.offsets[channel + 1];
        let (at, prefix) = (&mut next[channel], &mut channel_prefix[channel]);
        while *at < end && counts(row.labelled[*at].0, p.rank) {
            *prefix += row.labelled[*at].1;
            *at += 1;
        }
        while next_pooled < row.pooled.len() && counts(row.pooled[next_pooled].0, p.rank) {
            pooled_prefix += row.pooled[next_pooled].1;
            next_pooled += 1;
        }
        // The chains of `lane_half_products`: probe j goes to chain j mod UNROLL.
        let k = j % UNROLL;
        ll[k] = p.e_minus.mul_add(*prefix, ll[k]);
        sp[k] = p.e_minus.mul_add(pooled_prefix, sp[k]);
    }
    let total = |a: &[f64; UNROLL]| (a[0] + a[1]) + (a[2] + a[3]);
    (total(&ll), total(&sp))
}

/// `[Σ_n ⟨u_n, v_n⟩, ⟨∪u, ∪v⟩]` halves of the rows `rows` against every column: entry
/// `(a, b)` is the row `a`'s `P(≤ t)` sum over column `b` above the diagonal and its `P(< t)`
/// sum below (0 on it), so the cross products of `a < b` are `(a, b) + (b, a)`. Row `a` is
/// `2N` values, the labelled-line halves of every column then the pooled ones; rows follow each
/// other. Blocks of [`LANES`] rows run in parallel, each block tabulated once in lanes and each
/// column read once per block; an entry does not depend on the blocking (each lane is the same
/// sums in the same order as its row alone), so neither on the thread count nor on which rows
/// are asked for.
pub(super) fn half_product_rows(
    samples: &[CentredSample],
    grid: &Grid,
    rows: Range<usize>,
) -> Vec<f64> {
    let n = samples.len();
    let row_width = 2 * n.max(1);
    let mut out = vec![0.0; rows.len() * 2 * n];
    out.par_chunks_mut(LANES * row_width)
        .enumerate()
        .for_each_init(BlockTables::default, |tables, (block, values)| {
            let first = rows.start + block * LANES;
            let count = values.len() / row_width;
            tables.fill(&samples[first..first + count], grid);
            // One table at a time over every column, so that it stays in the core's cache.
            half_products_of_block::<false>(tables, samples, grid, first, count, |t, b, v| {
                values[t * row_width + b] = v
            });
            half_products_of_block::<true>(tables, samples, grid, first, count, |t, b, v| {
                values[t * row_width + n + b] = v
            });
        });
    out
}

/// The half products of the block's rows `first..first + count` (lanes `0..count` of
/// `tables`) over every column, pooled when `POOLED` else labelled line, each given to
/// `store(lane, column, value)`.
fn half_products_of_block<const POOLED: bool>(
    tables: &BlockTables,
    samples: &[CentredSample],
    grid: &Grid,
    first: usize,
    count: usize,
    mut store: impl FnMut(usize, usize, f64),
) {
    let table = if POOLED {
        &tables.pooled
    } else {
        &tables.labelled
    };
    let overflow = &tables.overflow;
    for (b, column) in samples.iter().enumerate() {
        let values = if b < first {
            lane_half_products::<true, POOLED>(table, overflow, column, grid)
        } else if b >= first + count {
            lane_half_products::<false, POOLED>(table, overflow, column, grid)
        } else {
            // A row of the block: the rows before it take P(≤ t), those after P(< t).
            let after = lane_half_products::<false, POOLED>(table, overflow, column, grid);
            let before = lane_half_products::<true, POOLED>(table, overflow, column, grid);
            let row = b - first;
            std::array::from_fn(|l| match l.cmp(&row) {
                Ordering::Less => after[l],
                Ordering::Greater => before[l],
                Ordering::Equal => 0.0,
            })
        };
        for (t, &v) in values.iter().enumerate().take(count) {
            store(t, b, v);
        }
    }
}
