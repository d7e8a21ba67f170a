!> The BLAS's threads for a run. Debian's libblas.so.3 is OpenBLAS (pthreads) when
!> libopenblas0-pthread is installed, and OpenBLAS starts one thread per core whose workers
!> spin between the factorisation's BLAS calls: on 2 cores a staged run took as much system
!> time as user time, and two runs side by side (make batch -j2, Slurm arrays) lost half
!> their throughput to the spinning, while one thread was faster in wall time as well
!> (docs/performance.md, "BLAS threads"). So a run asks for one BLAS thread, unless the user
!> chose a number (OPENBLAS_NUM_THREADS, or CFRD_BLAS_THREADS, which wins). The call is
!> looked up at run time (dlsym), so that cfrd links and runs against any BLAS; with a BLAS
!> that is not OpenBLAS nothing is done.
module cfrd_blas_threads
    use, intrinsic :: iso_c_binding, only: c_int, c_ptr, c_funptr, c_null_ptr, c_char, &
                                           c_null_char, c_associated, c_f_procpointer
    implicit none
    private

    public :: set_blas_threads

    abstract interface
        subroutine set_threads_t(n) bind(C)
            import :: c_int
            integer(c_int), value :: n
        end subroutine set_threads_t
        integer(c_int) function shutdown_t() bind(C)
            import :: c_int
        end function shutdown_t
    end interface

    interface
        !> dlsym(3) with RTLD_DEFAULT (a null handle in glibc): the symbol in any loaded
        !> library, or null.
        type(c_funptr) function dlsym(handle, symbol) bind(C, name='dlsym')
            import :: c_ptr, c_funptr, c_char
            type(c_ptr), value :: handle
            character(kind=c_char), intent(in) :: symbol(*)
        end function dlsym
    end interface

contains

    !> Set the number of OpenBLAS threads: CFRD_BLAS_THREADS if set to a positive number,
    !> else nothing if OPENBLAS_NUM_THREADS is set (OpenBLAS read it when it was loaded),
    !> else 1. Returns the number set, or 0 when nothing was set (no OpenBLAS, or the
    !> user's OPENBLAS_NUM_THREADS stands).
    integer function set_blas_threads() result(threads)
        type(c_funptr) :: address
        procedure(set_threads_t), pointer :: set_threads
        character(len=32) :: value
        integer :: length, status, chosen
        threads = 0
        chosen = 1
        call get_environment_variable('CFRD_BLAS_THREADS', value, length, status)
        if (status == 0 .and. length > 0) then
            read (value, *, iostat=status) chosen
            if (status /= 0 .or. chosen < 1) chosen = 1
        else
            call get_environment_variable('OPENBLAS_NUM_THREADS', value, length, status)
            if (status == 0 .and. length > 0) return
        end if
        address = dlsym(c_null_ptr, 'openblas_set_num_threads'//c_null_char)
        if (.not. c_associated(address)) return
        call c_f_procpointer(address, set_threads)
        call set_threads(int(chosen, c_int))
        threads = chosen
        if (chosen == 1) call stop_idle_workers()
    end function set_blas_threads

    !> End OpenBLAS's worker threads once the BLAS runs on the calling thread alone.
    !> OpenBLAS (pthreads build) starts them when it is loaded, before any of cfrd runs,
    !> and openblas_set_num_threads(1) leaves them waiting: each spins on sched_yield for
    !> its timeout (2^28 cycles, about 0.1 s) before it sleeps, a whole core of CPU time
    !> through a short run (a sixth of the samples of a 10^3-quad run; docs/performance.md
    !> (r)). blas_thread_shutdown_ is the routine OpenBLAS calls itself at exit and before
    !> a fork: it wakes and joins the workers. One thread computes as before (the same
    !> single-threaded kernels), so nothing else changes; a larger count later would start
    !> the workers again (OpenBLAS's lazy initialisation).
    subroutine stop_idle_workers()
        type(c_funptr) :: address
        procedure(shutdown_t), pointer :: shutdown
        integer(c_int) :: status
        address = dlsym(c_null_ptr, 'blas_thread_shutdown_'//c_null_char)
        if (.not. c_associated(address)) return
        call c_f_procpointer(address, shutdown)
        status = shutdown()
    end subroutine stop_idle_workers
end module cfrd_blas_threads
