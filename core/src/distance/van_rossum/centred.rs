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
//! entries, so every ordered pair is one pass over the column's spikes. A single pair, where
//! tabulating would cost more than it saves, finds the same prefixes by walking the row's trains
//! alongside the column's spikes (the same sums in the same order: the same bits).

use rayon::prelude::*;
use std::cmp::Ordering;
use std::ops::Range;

/// Largest `span/(2τ)` for which the centred-exponential evaluation is used
/// ([module docs](super)).
pub const CENTRED_EXP_LIMIT: f64 = 690.0;

/// Target number of table cells per spike of a mean sample (pooled) or channel (labelled): the
/// grid is the next power of two at or above, so cells hold at most one spike of a row sample
/// with high probability. Spikes cluster in time (a slide's phases), so a probe often lands
/// near a row spike: 8 cells per spike keeps the overflow walks rare while a pair of tables
/// still fits the core's cache (3 cost 1.6–2× the CPU time on the artificial set; 16 is
/// slower again). The grid never changes a sum, only where its prefixes are read from.
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

/// The prefix of one table cell: before its first spike, after it, and where the rest of the
/// cell's spikes continue when there are more.
#[derive(Debug, Clone, Copy, Default)]
struct Cell {
    before: f64,
    after_first: f64,
    /// Rank of the cell's first spike; [`NO_SPIKE`] when empty.
    first_rank: u32,
    /// 0, or 1 + the index in [`PrefixTables::overflow`] of the cell's further spikes.
    overflow: u32,
}

/// A row sample's prefixes `P(≤ t)` tabulated on the grid (labelled line and pooled).
#[derive(Debug, Clone, Default)]
pub(super) struct PrefixTables {
    labelled: Vec<Cell>,
    pooled: Vec<Cell>,
    /// Runs of `(rank, prefix after the spike)` for the second and later spikes of a cell, each
    /// run ended by `(NO_SPIKE, _)`.
    overflow: Vec<(u32, f64)>,
}

impl PrefixTables {
    /// Tabulates `sample` (reusing the allocations).
    pub(super) fn fill(&mut self, sample: &CentredSample, grid: &Grid) {
        // Every cell is overwritten below.
        self.overflow.clear();
        self.pooled.resize(grid.pooled_cells, Cell::default());
        fill_train(
            &mut self.pooled,
            &mut self.overflow,
            &sample.pooled,
            grid.pooled_shift,
            0,
            1,
        );
        self.labelled
            .resize(grid.labelled_time_cells * grid.channels, Cell::default());
        for (c, w) in sample.offsets.windows(2).enumerate() {
            fill_train(
                &mut self.labelled,
                &mut self.overflow,
                &sample.labelled[w[0]..w[1]],
                grid.labelled_shift,
                c,
                grid.channels,
            );
        }
    }

    /// `P(≤ rank)` (or `P(< rank)` when `STRICT`) from cell `cell` of `cells`.
    #[inline(always)]
    fn prefix<const STRICT: bool>(&self, cells: &[Cell], cell: usize, rank: u32) -> f64 {
        let c = &cells[cell];
        let counted = if STRICT {
            c.first_rank < rank
        } else {
            c.first_rank <= rank
        };
        let p = if counted { c.after_first } else { c.before };
        if c.overflow == 0 {
            p
        } else {
            self.overflow_prefix::<STRICT>(c.overflow as usize - 1, rank, p)
        }
    }

    /// Continues a cell's prefix over its second and later spikes.
    #[cold]
    #[inline(never)]
    fn overflow_prefix<const STRICT: bool>(&self, start: usize, rank: u32, mut p: f64) -> f64 {
        for &(r, after) in &self.overflow[start..] {
            let counted = if STRICT { r < rank } else { r <= rank };
            if !counted {
                break;
            }
            p = after;
        }
        p
    }
}

/// Probes handled per step of [`half_products`] (independent accumulator chains).
const UNROLL: usize = 4;

/// `(Σ_{j ∈ b} e⁻_j·P(t_j))` over the column `b`, labelled line and pooled, for each of `B` row
/// tables at once (the column is read once), with `P(≤ t)` or, when `STRICT`, `P(< t)`. The
/// summation order is the same for every `B`.
fn half_products<const STRICT: bool, const B: usize>(
    tables: [&PrefixTables; B],
    column: &CentredSample,
    grid: &Grid,
) -> [(f64, f64); B] {
    let mut ll = [[0.0f64; UNROLL]; B];
    let mut sp = [[0.0f64; UNROLL]; B];
    let chunks = column.probes.chunks_exact(UNROLL);
    let rest = chunks.remainder();
    for chunk in chunks {
        // Constant chain indices, so the accumulators stay in registers.
        probe::<STRICT, B>(&tables, &chunk[0], grid, &mut ll, &mut sp, 0);
        probe::<STRICT, B>(&tables, &chunk[1], grid, &mut ll, &mut sp, 1);
        probe::<STRICT, B>(&tables, &chunk[2], grid, &mut ll, &mut sp, 2);
        probe::<STRICT, B>(&tables, &chunk[3], grid, &mut ll, &mut sp, 3);
    }
    for (k, p) in rest.iter().enumerate() {
        probe::<STRICT, B>(&tables, p, grid, &mut ll, &mut sp, k);
    }
    let total = |a: &[f64; UNROLL]| (a[0] + a[1]) + (a[2] + a[3]);
    std::array::from_fn(|t| (total(&ll[t]), total(&sp[t])))
}

/// Fills the cells `first + g·stride` (`g` the time cell) with the prefixes of one train
/// `(rank, e⁺)` in time order.
fn fill_train(
    cells: &mut [Cell],
    overflow: &mut Vec<(u32, f64)>,
    train: &[(u32, f64)],
    shift: u32,
    first: usize,
    stride: usize,
) {
    let mut prefix = 0.0;
    let mut spikes = train.iter().peekable();
    for (g, cell) in cells.iter_mut().skip(first).step_by(stride).enumerate() {
        let before = prefix;
        *cell = match spikes.next_if(|&&(r, _)| (r >> shift) as usize == g) {
            None => Cell {
                before,
                after_first: before,
                first_rank: NO_SPIKE,
                overflow: 0,
            },
            Some(&(first_rank, e_plus)) => {
                prefix += e_plus;
                let after_first = prefix;
                let mut more = 0;
                while let Some(&(r, e_plus)) = spikes.next_if(|&&(r, _)| (r >> shift) as usize == g)
                {
                    if more == 0 {
                        more = overflow.len() as u32 + 1;
                    }
                    prefix += e_plus;
                    overflow.push((r, prefix));
                }
                if more != 0 {
                    overflow.push((NO_SPIKE, prefix));
                }
                Cell {
                    before,
                    after_first,
                    first_rank,
                    overflow: more,
                }
            }
        };
    }
}

/// `Σ_n ⟨u_n, v_n⟩` and `⟨∪u, ∪v⟩` between two samples, as the sum of the two entries of
/// [`half_product_rows`], bit for bit, without tabulating either sample.
pub(super) fn cross_pair(a: &CentredSample, b: &CentredSample, grid: &Grid) -> (f64, f64) {
    let (ll_ab, sp_ab) = merged_half_products::<false>(a, b, grid);
    let (ll_ba, sp_ba) = merged_half_products::<true>(b, a, grid);
    (ll_ab + ll_ba, sp_ab + sp_ba)
}

/// [`half_products`] of the row sample `row` over `column`, with each prefix found by walking
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
        // The chains of `half_products`: probe j goes to chain j mod UNROLL.
        let k = j % UNROLL;
        ll[k] = p.e_minus.mul_add(*prefix, ll[k]);
        sp[k] = p.e_minus.mul_add(pooled_prefix, sp[k]);
    }
    let total = |a: &[f64; UNROLL]| (a[0] + a[1]) + (a[2] + a[3]);
    (total(&ll), total(&sp))
}

/// One probe of [`half_products`] into accumulator chain `k` of every table.
#[inline(always)]
fn probe<const STRICT: bool, const B: usize>(
    tables: &[&PrefixTables; B],
    p: &Probe,
    grid: &Grid,
    ll: &mut [[f64; UNROLL]; B],
    sp: &mut [[f64; UNROLL]; B],
    k: usize,
) {
    let pooled_cell = grid.pooled_cell(p.rank);
    for t in 0..B {
        let table = tables[t];
        let l = table.prefix::<STRICT>(&table.labelled, p.labelled_cell as usize, p.rank);
        let s = table.prefix::<STRICT>(&table.pooled, pooled_cell, p.rank);
        ll[t][k] = p.e_minus.mul_add(l, ll[t][k]);
        sp[t][k] = p.e_minus.mul_add(s, sp[t][k]);
    }
}

/// Rows tabulated together, each column read once for all of them.
const ROW_BLOCK: usize = 2;

/// `[Σ_n ⟨u_n, v_n⟩, ⟨∪u, ∪v⟩]` halves of the rows `rows` against every column: entry
/// `(a, b)` is the row `a`'s `P(≤ t)` sum over column `b` above the diagonal and its `P(< t)`
/// sum below (0 on it), so the cross products of `a < b` are `(a, b) + (b, a)`. Row `a` is
/// `2N` values, the labelled-line halves of every column then the pooled ones; rows follow each
/// other. Blocks of [`ROW_BLOCK`] rows run in parallel, each row from its own table and each
/// column read once per block; an entry does not depend on the blocking (the same sums in the
/// same order), so neither on the thread count nor on which rows are asked for.
pub(super) fn half_product_rows(
    samples: &[CentredSample],
    grid: &Grid,
    rows: Range<usize>,
) -> Vec<f64> {
    let n = samples.len();
    let row_width = 2 * n.max(1);
    let mut out = vec![0.0; rows.len() * 2 * n];
    out.par_chunks_mut(ROW_BLOCK * row_width)
        .enumerate()
        .for_each_init(
            || std::array::from_fn::<_, ROW_BLOCK, _>(|_| PrefixTables::default()),
            |tables, (block, values)| {
                let first = rows.start + block * ROW_BLOCK;
                let count = values.len() / row_width;
                for (t, table) in tables.iter_mut().enumerate().take(count) {
                    table.fill(&samples[first + t], grid);
                }
                let mut store = |t: usize, b: usize, (l, s): (f64, f64)| {
                    values[t * row_width + b] = l;
                    values[t * row_width + n + b] = s;
                };
                for (b, column) in samples.iter().enumerate() {
                    if count == ROW_BLOCK && !(first..first + ROW_BLOCK).contains(&b) {
                        // The column is on the same side of every row of the block.
                        let all = std::array::from_fn(|t| &tables[t]);
                        let values = if b < first {
                            half_products::<true, ROW_BLOCK>(all, column, grid)
                        } else {
                            half_products::<false, ROW_BLOCK>(all, column, grid)
                        };
                        for (t, v) in values.into_iter().enumerate() {
                            store(t, b, v);
                        }
                        continue;
                    }
                    for (t, table) in tables.iter().enumerate().take(count) {
                        let [v] = match b.cmp(&(first + t)) {
                            Ordering::Greater => half_products::<false, 1>([table], column, grid),
                            Ordering::Less => half_products::<true, 1>([table], column, grid),
                            Ordering::Equal => continue,
                        };
                        store(t, b, v);
                    }
                }
            },
        );
    out
}
