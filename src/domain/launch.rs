//! What an MPI launcher tells a process through its environment, read without initialising
//! MPI: whether it is one of a job's processes, the job's size, and how many of them share
//! its machine.

/// Whether an MPI launcher started this process: Open MPI's `mpirun`, a PMI launcher
/// (MPICH's Hydra, Slurm's `srun --mpi=pmi2`) or a PMIx one (`srun --mpi=pmix`, PRRTE).
pub fn launched() -> bool {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"]
        .iter()
        .any(|k| std::env::var_os(k).is_some())
}

/// The job's size where the launcher says it (Open MPI, PMI; a PMIx launcher does not).
pub fn launched_size() -> Option<usize> {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"]
        .iter()
        .find_map(|k| std::env::var(k).ok()?.parse().ok())
}

/// How many processes of the job the launcher started on this machine (Open MPI, MPICH).
pub fn launched_local_size() -> Option<usize> {
    ["OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"]
        .iter()
        .find_map(|k| std::env::var(k).ok()?.parse().ok())
}
