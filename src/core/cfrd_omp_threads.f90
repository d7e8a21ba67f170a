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
!> s of CPU time (docs/performance.md (m)); README says to set it. A parallel region that
!> gets one thread runs in place, without a team (cfrd_omp_in_place.c; docs/performance.md
!> (ae)): regions_in_place counts them.
module cfrd_omp_threads
    use, intrinsic :: iso_c_binding, only: c_long_long
    !$ use omp_lib, only: omp_set_num_threads, omp_get_max_threads, &
    !$                    omp_get_max_active_levels, omp_set_max_active_levels
    implicit none
    private

    public :: set_omp_threads, loop_threads, begin_serial_library, end_serial_library
    public :: regions_in_place

    interface
        !> cfrd_omp_in_place.c: the parallel regions run in place so far.
        integer(c_long_long) function c_regions_in_place() &
            bind(C, name='cfrd_omp_regions_in_place')
            import :: c_long_long
        end function c_regions_in_place
    end interface

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

    !> Make the parallel regions of the library called next run on the calling thread
    !> alone, until end_serial_library(saved): no active level is allowed (OpenMP's
    !> max-active-levels = 0). CHOLMOD's supernodal factorisation (SuiteSparse 5, Debian's
    !> build with OpenMP) opens several small parallel loops per supernode with a fixed
    !> team of CHOLMOD_OMP_NUM_THREADS = 4, whatever omp_set_num_threads says: on 2 cores
    !> its 3 extra threads were created at the first factorisation and spun or slept on
    !> futexes between the loops (21,000 futex calls in a 10^4-quad run). Those loops
    !> zero, map and scatter, each entry written by one iteration, with no reduction, so
    !> the factor is the same bits on one thread (docs/performance.md (r)). Returns the
    !> setting to restore.
    integer function begin_serial_library() result(saved)
        saved = 1
        !$ saved = omp_get_max_active_levels()
        !$ call omp_set_max_active_levels(0)
    end function begin_serial_library

    !> The parallel regions of the process run in place so far, without a team of threads
    !> (cfrd_omp_in_place.c): those that would get one thread.
    integer(c_long_long) function regions_in_place()
        regions_in_place = c_regions_in_place()
    end function regions_in_place

    !> Restore the setting that begin_serial_library returned.
    subroutine end_serial_library(saved)
        integer, intent(in) :: saved
        !$ call omp_set_max_active_levels(saved)
    end subroutine end_serial_library
end module cfrd_omp_threads
