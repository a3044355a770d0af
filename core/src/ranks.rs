//! Ranks: the processes one computation is split over.
//!
//! neurotac scales out the way NEST and Arbor do: several processes ("ranks", numbered
//! `0 … size−1`) each compute a block of the work, and a collective **all-gather** gives every
//! rank every block. [`Ranks`] is that interface. [`OneProcess`] is the trivial group of one;
//! `neurotac-cluster` implements it over MPI (the `mpi` feature); [`ThreadRanks`] runs a group
//! as threads of one process, so tests can check that results do not depend on the rank count
//! without an MPI installation.
//!
//! Every collective must be called by every rank of the group, in the same order, or the group
//! deadlocks (as in MPI). Work is split by [`balanced_blocks`]: contiguous blocks of items whose
//! summed costs are as equal as the items allow, so block `r` is the same on every rank and a
//! result assembled in rank order equals the one-process result.

use std::ops::Range;
use std::sync::{Arc, Barrier, Mutex};
use thiserror::Error;

/// A failed collective operation.
#[derive(Debug, Error)]
pub enum RanksError {
    /// The communication layer reported an error (a rank died, a message was cut …).
    #[error("communication between ranks failed during {during}: {reason}")]
    Communication {
        /// The operation in progress.
        during: &'static str,
        /// What the layer said.
        reason: String,
    },
    /// A gathered block does not have the shape the protocol expects.
    #[error("rank {rank} sent a malformed block during {during}: {reason}")]
    Malformed {
        /// The rank whose block was malformed.
        rank: usize,
        /// The operation in progress.
        during: &'static str,
        /// What was wrong.
        reason: String,
    },
}

/// A group of processes computing one result together (see the [module docs](self)).
///
/// `Sync`, so a command running inside a thread pool can hold it; the collectives of one
/// group are still called one at a time, in the same order on every rank.
pub trait Ranks: Sync {
    /// This process's rank, `0 … size−1`.
    fn rank(&self) -> usize;

    /// The number of ranks in the group (≥ 1).
    fn size(&self) -> usize;

    /// Every rank's `local` bytes, in rank order, on every rank. Collective.
    fn all_gather_bytes(&self, local: &[u8]) -> Result<Vec<Vec<u8>>, RanksError>;

    /// `true` on rank 0, the rank that writes outputs and prints.
    fn is_root(&self) -> bool {
        self.rank() == 0
    }
}

/// The group of one: no communication.
#[derive(Debug, Clone, Copy, Default)]
pub struct OneProcess;

impl Ranks for OneProcess {
    fn rank(&self) -> usize {
        0
    }

    fn size(&self) -> usize {
        1
    }

    fn all_gather_bytes(&self, local: &[u8]) -> Result<Vec<Vec<u8>>, RanksError> {
        Ok(vec![local.to_vec()])
    }
}

/// Every rank's `f64` values concatenated in rank order, on every rank. Collective.
pub fn all_gather_f64(ranks: &dyn Ranks, local: &[f64]) -> Result<Vec<f64>, RanksError> {
    all_gather_words(ranks, local, f64::to_le_bytes, f64::from_le_bytes, "f64")
}

/// Every rank's `u32` values concatenated in rank order, on every rank. Collective.
pub fn all_gather_u32(ranks: &dyn Ranks, local: &[u32]) -> Result<Vec<u32>, RanksError> {
    all_gather_words(ranks, local, u32::to_le_bytes, u32::from_le_bytes, "u32")
}

/// Values of `W` little-endian bytes each, all-gathered.
fn all_gather_words<T: Copy, const W: usize>(
    ranks: &dyn Ranks,
    local: &[T],
    to_bytes: fn(T) -> [u8; W],
    from_bytes: fn([u8; W]) -> T,
    name: &'static str,
) -> Result<Vec<T>, RanksError> {
    let bytes: Vec<u8> = local.iter().flat_map(|&v| to_bytes(v)).collect();
    let mut out = Vec::with_capacity(local.len() * ranks.size());
    for (rank, block) in ranks.all_gather_bytes(&bytes)?.into_iter().enumerate() {
        if block.len() % W != 0 {
            return Err(RanksError::Malformed {
                rank,
                during: "all-gather of values",
                reason: format!("{} bytes is not a whole number of {name}", block.len()),
            });
        }
        out.extend(
            block
                .chunks_exact(W)
                .map(|c| from_bytes(c.try_into().expect("chunks of W bytes"))),
        );
    }
    Ok(out)
}

/// Splits items `0 … costs.len()` into `parts` contiguous blocks whose summed costs are as
/// equal as possible: block `r` ends at the first item where the running cost reaches
/// `(r+1)/parts` of the total. Blocks may be empty (more parts than items); together they
/// cover every item once, in order. Costs must be finite and ≥ 0 (others count as 0).
pub fn balanced_blocks(costs: &[f64], parts: usize) -> Vec<Range<usize>> {
    let parts = parts.max(1);
    let clean = |c: f64| if c.is_finite() && c > 0.0 { c } else { 0.0 };
    let total: f64 = costs.iter().copied().map(clean).sum();
    let mut blocks = Vec::with_capacity(parts);
    let (mut start, mut item, mut running) = (0, 0, 0.0);
    for r in 0..parts {
        if r + 1 == parts {
            blocks.push(start..costs.len());
            break;
        }
        let target = total * (r + 1) as f64 / parts as f64;
        // Take items while the block's share is not reached, taking the item that crosses
        // the target when that leaves the running cost closer to it.
        while item < costs.len() {
            let next = running + clean(costs[item]);
            if next <= target || (next - target) < (target - running) {
                running = next;
                item += 1;
            } else {
                break;
            }
        }
        blocks.push(start..item);
        start = item;
    }
    blocks
}

/// The block of `items` equal-cost items that `rank` of `size` computes ([`balanced_blocks`]
/// with unit costs).
pub fn even_block(items: usize, rank: usize, size: usize) -> Range<usize> {
    let size = size.max(1);
    let lo = items * rank / size;
    let hi = items * (rank + 1) / size;
    lo.min(items)..hi.min(items)
}

/// A group of ranks that are threads of one process: for tests of rank-count independence
/// without MPI. Make the group with [`ThreadRanks::group`] and move one member to each thread.
pub struct ThreadRanks {
    rank: usize,
    shared: Arc<ThreadShared>,
}

struct ThreadShared {
    size: usize,
    barrier: Barrier,
    slots: Mutex<Vec<Vec<u8>>>,
}

impl ThreadRanks {
    /// `size` members of one group, rank 0 first.
    pub fn group(size: usize) -> Vec<ThreadRanks> {
        let size = size.max(1);
        let shared = Arc::new(ThreadShared {
            size,
            barrier: Barrier::new(size),
            slots: Mutex::new(vec![Vec::new(); size]),
        });
        (0..size)
            .map(|rank| ThreadRanks {
                rank,
                shared: Arc::clone(&shared),
            })
            .collect()
    }

    /// Runs `f` on every member of a group of `size`, each in its own thread, and returns the
    /// results in rank order.
    pub fn run<T: Send>(size: usize, f: impl Fn(&ThreadRanks) -> T + Sync) -> Vec<T> {
        let group = Self::group(size);
        std::thread::scope(|s| {
            let handles: Vec<_> = group.iter().map(|r| s.spawn(|| f(r))).collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("a rank thread panicked"))
                .collect()
        })
    }
}

impl Ranks for ThreadRanks {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.shared.size
    }

    fn all_gather_bytes(&self, local: &[u8]) -> Result<Vec<Vec<u8>>, RanksError> {
        let poisoned = |_| RanksError::Communication {
            during: "thread all-gather",
            reason: "a rank thread panicked".into(),
        };
        self.shared.slots.lock().map_err(poisoned)?[self.rank] = local.to_vec();
        self.shared.barrier.wait();
        let all = self.shared.slots.lock().map_err(poisoned)?.clone();
        // Nobody writes the next round's slot before everyone has read this one.
        self.shared.barrier.wait();
        Ok(all)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balanced_blocks_cover_every_item_once_in_order() {
        for n in [0usize, 1, 2, 5, 17, 100] {
            for parts in 1..=6 {
                let costs: Vec<f64> = (0..n).map(|i| (n - i) as f64).collect();
                let blocks = balanced_blocks(&costs, parts);
                assert_eq!(blocks.len(), parts);
                let mut next = 0;
                for b in &blocks {
                    assert_eq!(b.start, next);
                    next = b.end;
                }
                assert_eq!(next, n);
            }
        }
    }

    #[test]
    fn balanced_blocks_balance_a_triangle() {
        // Row i of an upper triangle costs n − i − 1 pairs.
        let n = 1000;
        let costs: Vec<f64> = (0..n).map(|i| (n - i - 1) as f64).collect();
        let total: f64 = costs.iter().sum();
        for parts in [2, 3, 8] {
            for b in balanced_blocks(&costs, parts) {
                let share: f64 = costs[b].iter().sum();
                assert!(
                    (share / total - 1.0 / parts as f64).abs() < 0.002,
                    "{share} of {total}"
                );
            }
        }
        // Equal costs give equal blocks, more parts than items give empty ones.
        assert_eq!(balanced_blocks(&[1.0; 4], 2), vec![0..2, 2..4]);
        assert_eq!(balanced_blocks(&[1.0; 2], 3), vec![0..1, 1..1, 1..2]);
    }

    #[test]
    fn even_blocks_partition_the_items() {
        for items in [0, 1, 7, 10] {
            for size in 1..5 {
                let blocks: Vec<_> = (0..size).map(|r| even_block(items, r, size)).collect();
                assert_eq!(blocks.first().unwrap().start, 0);
                assert_eq!(blocks.last().unwrap().end, items);
                assert!(blocks.windows(2).all(|w| w[0].end == w[1].start));
            }
        }
    }

    #[test]
    fn thread_ranks_all_gather_in_rank_order_repeatedly() {
        let results = ThreadRanks::run(3, |r| {
            let mut seen = Vec::new();
            for round in 0..4u32 {
                let local: Vec<u32> = (0..=r.rank() as u32).map(|i| round * 100 + i).collect();
                seen.push(all_gather_u32(r, &local).unwrap());
            }
            seen
        });
        for seen in &results {
            assert_eq!(seen, &results[0]);
            assert_eq!(seen[2], vec![200, 200, 201, 200, 201, 202]);
        }
        let one = all_gather_f64(&OneProcess, &[1.5, -2.0]).unwrap();
        assert_eq!(one, vec![1.5, -2.0]);
    }
}
