!> The OpenMP threads of a run: the element loops of assembly, internal forces and stress
!> update (cfrd_assembly, cfrd_increment) run on this many threads; the factorisation and
!> the solves do not (their BLAS keeps its own, one, thread: cfrd_blas_threads). The count
!> is `cfrd --threads N` if given, else OMP_NUM_THREADS if set (the OpenMP runtime reads it
!> itself), else 1 [choice]: a study runs decks side by side, one per core (make batch,
!> Slurm arrays), and a second thread per run would only compete with the other runs
!> (docs/performance.md, "OpenMP"). The results are the same bits for any count: the
!> threads compute element contributions into storage of their own, and the sums are
!> taken in the one serial order (cfrd_assembly). Built without OpenMP, the program runs
!> one thread whatever is asked. With more than one thread, libgomp's idle workers spin
!> for a while after each loop unless OMP_WAIT_POLICY=passive, which libgomp reads when it
!> is loaded, before any Fortran runs: on a shared machine a 2-thread run spun through 6.5
!> s of CPU time (docs/performance.md (m)); README says to set it.
module cfrd_omp_threads
    !$ use omp_lib, only: omp_set_num_threads, omp_get_max_threads
    implicit none
    private

    public :: set_omp_threads, loop_threads

contains

    !> Set the threads of the element loops: `requested` when positive, else
    !> OMP_NUM_THREADS when set, else 1. Returns the number the loops will use (1 without
    !> OpenMP).
    integer function set_omp_threads(requested) result(threads)
        integer, intent(in) :: requested
        character(len=32) :: value
        integer :: length, status
        threads = 1
        if (requested > 0) then
            !$ call omp_set_num_threads(requested)
        else
            call get_environment_variable('OMP_NUM_THREADS', value, length, status)
            if (.not. (status == 0 .and. length > 0)) then
                !$ call omp_set_num_threads(1)
            end if
        end if
        !$ threads = omp_get_max_threads()
    end function set_omp_threads

    !> The threads the next element loop will use (1 without OpenMP).
    integer function loop_threads() result(threads)
        threads = 1
        !$ threads = omp_get_max_threads()
    end function loop_threads
end module cfrd_omp_threads
