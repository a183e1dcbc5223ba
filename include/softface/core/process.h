#ifndef softface_process_h
#define softface_process_h

namespace softface
{
  /**
   * What a softface process does before and after its computations,
   * independent of the scene.
   */
  namespace Process
  {
    /**
     * Call before MPI is initialised. A serial run (no mpirun, srun or other
     * launcher in the environment) asks Open MPI not to start its helper
     * process (orted): Trilinos needs MPI initialised, but a run on one rank
     * gained nothing from the helper and paid its start-up. A
     * setting of OMPI_MCA_ess_singleton_isolated in the environment wins.
     * An isolated process gets a session directory of its own
     * (`$TMPDIR/softface-mpi.<pid>`, removed at exit), so that concurrent
     * runs do not race on a shared one, and Open MPI's local transport
     * only (OMPI_MCA_pml = ob1, OMPI_MCA_btl = self, unless set), so that
     * MPI_Init does not probe for networks.
     */
    void
    prepare_serial_mpi();

    /**
     * Seconds since this process started (from /proc, 10 ms resolution),
     * so the printed wall time includes loading the shared libraries and
     * initialising MPI, as the shell's `time` sees it. Falls back to the
     * time since the first call where /proc is not readable.
     */
    double
    wall_time();
  } // namespace Process
} // namespace softface

#endif
