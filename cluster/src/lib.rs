//! # neurotac-cluster
//!
//! neurotac on several processes. [`Cluster::from_environment`] tells how this process was
//! started: alone (a group of one, [`neurotac_core::OneProcess`]) or by `mpirun -n K` (MPI
//! rank `r` of `K`, through rsmpi over the system's MPI library, when built with the `mpi`
//! feature). A [`Cluster`] is a [`Ranks`]: the distributed computations of neurotac-core and
//! neurotac-experiments take it and split their work over its ranks, all-gathering the blocks,
//! so every rank ends with the one-process result (see [`neurotac_core::ranks`]).
//!
//! A build without the `mpi` feature started by `mpirun` with more than one rank would run the
//! whole job K times, racing on the same outputs; [`Cluster::from_environment`] refuses it with
//! [`ClusterError::NotBuiltWithMpi`] instead.
//!
//! Ranks started on different data or with different settings (an MPMD launch, a file that
//! differs between machines) would each contribute blocks of another computation. Before any
//! work the ranks compare a [`RunDigest`] of their settings and inputs
//! ([`Cluster::agree_on`], the [`agreement`] module) and all stop with
//! [`ClusterError::Disagree`] when one differs.
//!
//! ```
//! use neurotac_cluster::Cluster;
//! use neurotac_core::Ranks;
//! // Not started by mpirun: one process.
//! let cluster = Cluster::from_environment()?;
//! assert_eq!(cluster.size(), 1);
//! # Ok::<(), neurotac_cluster::ClusterError>(())
//! ```
#![deny(missing_docs)]

pub mod agreement;

pub use agreement::{DigestPart, Disagreement, PartKind, RunDigest};
use neurotac_core::{OneProcess, Ranks, RanksError};
use thiserror::Error;

/// Why this process cannot join its group, or its group cannot run together.
#[derive(Debug, Error)]
pub enum ClusterError {
    /// Started by an MPI launcher with several ranks, but built without the `mpi` feature.
    #[error(
        "started by mpirun as rank {rank} of {size}, but this neurotac was built without MPI; \
         rebuild with `cargo build --release -p neurotac-cli --features mpi` \
         (see README \"Running on several machines\")"
    )]
    NotBuiltWithMpi {
        /// This process's rank as the launcher set it.
        rank: usize,
        /// The rank count the launcher set.
        size: usize,
    },
    /// The MPI library could not be initialised.
    #[error("MPI could not be initialised (was MPI already initialised in this process?)")]
    MpiInit,
    /// A rank was started with other settings or read other inputs than rank 0
    /// ([`Cluster::agree_on`]): the first difference found, the same on every rank.
    #[error(transparent)]
    Disagree(#[from] Disagreement),
    /// The ranks could not exchange what they need.
    #[error(transparent)]
    Ranks(#[from] RanksError),
}

/// The launcher's view of this process, from the environment variables MPI launchers set
/// (Open MPI's `OMPI_COMM_WORLD_RANK`/`_SIZE`; PMI's `PMI_RANK`/`PMI_SIZE` for MPICH and
/// Slurm): `Some((rank, size))` when started by one.
pub fn launcher_ranks() -> Option<(usize, usize)> {
    let read = |name: &str| std::env::var(name).ok()?.trim().parse::<usize>().ok();
    [
        ("OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE"),
        ("PMI_RANK", "PMI_SIZE"),
    ]
    .into_iter()
    .find_map(|(rank, size)| Some((read(rank)?, read(size)?)))
}

/// The group this process belongs to.
pub enum Cluster {
    /// Not started by an MPI launcher (or a launch with one rank, without the `mpi` feature).
    One(OneProcess),
    /// An MPI rank (the `mpi` feature, started by `mpirun`).
    #[cfg(feature = "mpi")]
    Mpi(mpi_ranks::MpiRanks),
}

impl Cluster {
    /// The group as the launcher made it (see the [crate docs](crate)). With the `mpi`
    /// feature, MPI is initialised only when a launcher started the process.
    pub fn from_environment() -> Result<Self, ClusterError> {
        match launcher_ranks() {
            #[cfg(feature = "mpi")]
            Some(_) => Ok(Cluster::Mpi(mpi_ranks::MpiRanks::initialise()?)),
            #[cfg(not(feature = "mpi"))]
            Some((rank, size)) if size > 1 => Err(ClusterError::NotBuiltWithMpi { rank, size }),
            _ => Ok(Cluster::One(OneProcess)),
        }
    }

    /// Checks that every rank was started with the same settings on the same inputs: each
    /// rank's `digest` is all-gathered and compared with rank 0's (see [`RunDigest`]). Call it
    /// on every rank before any work; on a difference every rank returns the same
    /// [`ClusterError::Disagree`], naming the first rank and part that differ. A group of one
    /// agrees without communication. Collective.
    pub fn agree_on(&self, digest: &RunDigest) -> Result<(), ClusterError> {
        Ok(agreement::agree_on(self, digest)??)
    }

    /// Ends the whole group at once with exit code `code` (MPI_Abort): for a rank that failed
    /// alone, while the others may wait for it in a collective. A group of one just exits.
    pub fn abort(&self, code: i32) -> ! {
        match self {
            Cluster::One(_) => std::process::exit(code),
            #[cfg(feature = "mpi")]
            Cluster::Mpi(m) => m.abort(code),
        }
    }
}

impl Ranks for Cluster {
    fn rank(&self) -> usize {
        match self {
            Cluster::One(o) => o.rank(),
            #[cfg(feature = "mpi")]
            Cluster::Mpi(m) => m.rank(),
        }
    }

    fn size(&self) -> usize {
        match self {
            Cluster::One(o) => o.size(),
            #[cfg(feature = "mpi")]
            Cluster::Mpi(m) => m.size(),
        }
    }

    fn all_gather_bytes(&self, local: &[u8]) -> Result<Vec<Vec<u8>>, RanksError> {
        match self {
            Cluster::One(o) => o.all_gather_bytes(local),
            #[cfg(feature = "mpi")]
            Cluster::Mpi(m) => m.all_gather_bytes(local),
        }
    }
}

#[cfg(feature = "mpi")]
mod mpi_ranks {
    //! [`Ranks`] over MPI_COMM_WORLD (rsmpi).

    use super::ClusterError;
    use mpi::datatype::PartitionMut;
    use mpi::environment::Universe;
    use mpi::topology::SimpleCommunicator;
    use mpi::traits::{Communicator, CommunicatorCollectives};
    use mpi::{Count, Threading};
    use neurotac_core::{Ranks, RanksError};
    use std::sync::Mutex;

    /// This process as a rank of MPI_COMM_WORLD. MPI is finalised when it is dropped.
    pub struct MpiRanks {
        world: SimpleCommunicator,
        /// Held through every MPI call: MPI runs at the serialised threading level.
        lock: Mutex<()>,
        // Dropped last: finalises MPI.
        _universe: Universe,
    }

    impl MpiRanks {
        /// Initialises MPI. Calls may come from any one thread at a time (a rayon pool's
        /// thread runs a command), so the serialised threading level is asked for.
        pub(super) fn initialise() -> Result<Self, ClusterError> {
            let (universe, _) = mpi::initialize_with_threading(Threading::Serialized)
                .ok_or(ClusterError::MpiInit)?;
            Ok(Self {
                world: universe.world(),
                lock: Mutex::new(()),
                _universe: universe,
            })
        }

        pub(super) fn abort(&self, code: i32) -> ! {
            self.world.abort(code)
        }
    }

    // SAFETY: MPI was initialised at `Threading::Serialized`, which allows MPI calls from any
    // thread as long as no two run at once; every collective call goes through `lock`, and
    // rank/size/abort only read the communicator's constant handle.
    unsafe impl Send for MpiRanks {}
    // SAFETY: as for `Send`.
    unsafe impl Sync for MpiRanks {}

    fn too_large(what: usize) -> RanksError {
        RanksError::Communication {
            during: "MPI all-gather",
            reason: format!("{what} bytes exceed MPI's 2^31 − 1 per message"),
        }
    }

    impl Ranks for MpiRanks {
        fn rank(&self) -> usize {
            self.world.rank() as usize
        }

        fn size(&self) -> usize {
            self.world.size() as usize
        }

        fn all_gather_bytes(&self, local: &[u8]) -> Result<Vec<Vec<u8>>, RanksError> {
            let _serialised = self.lock.lock().unwrap_or_else(|p| p.into_inner());
            let size = self.size();
            let own = Count::try_from(local.len()).map_err(|_| too_large(local.len()))?;
            let mut counts = vec![0 as Count; size];
            self.world.all_gather_into(&own, &mut counts[..]);
            let mut displs = Vec::with_capacity(size);
            let mut total: usize = 0;
            for &c in &counts {
                displs.push(Count::try_from(total).map_err(|_| too_large(total))?);
                total += c as usize;
            }
            let mut all = vec![0u8; total];
            // Every rank holds the same counts, so all of them skip an all-empty gather alike.
            // An empty buffer's pointer is dangling (address 1 for bytes), which Open MPI takes
            // for MPI_IN_PLACE: a receive buffer there is MPI_ERR_ARG, a send buffer is read as
            // "in place". Empty blocks are sent from a real address instead.
            if total > 0 {
                let real = [0u8; 1];
                let send = if local.is_empty() { &real[..0] } else { local };
                let mut partition = PartitionMut::new(&mut all[..], &counts[..], &displs[..]);
                self.world.all_gather_varcount_into(send, &mut partition);
            }
            let mut out = Vec::with_capacity(size);
            let mut rest = &all[..];
            for &c in &counts {
                let (block, tail) = rest.split_at(c as usize);
                out.push(block.to_vec());
                rest = tail;
            }
            Ok(out)
        }
    }
}
