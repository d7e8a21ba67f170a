!> A stop asked for from outside: SIGINT (Ctrl-C) or SIGTERM (what Slurm sends at a job's time
!> limit, and `kill`'s default). catch_stop_signals installs a handler that only records the
!> signal; the analysis asks stop_signal() between increments and stops with stop_error, and
!> the command line keeps the completed stages as DECK.incomplete.h5 like after a numerical
!> failure (docs/results.md, "Stopped runs"). A second signal of the same kind is not caught:
!> it ends the program at once (as SIGKILL would; DECK.h5.part stays readable).
module cfrd_signals
    use, intrinsic :: iso_c_binding, only: c_int, c_funptr, c_funloc, c_null_funptr
    use cfrd_error, only: error_t, fatal_error, interrupt_error, terminate_error
    implicit none
    private

    public :: catch_stop_signals, stop_signal, signal_name, stop_error
    public :: sigint, sigterm

    !> Signal numbers: fixed by POSIX practice on every Unix cfrd runs on.
    integer(c_int), parameter :: sigint = 2, sigterm = 15

    !> The first stop signal received (0: none). The one mutable module variable of cfrd: a
    !> signal handler takes no argument but the signal, so there is no other place for it.
    !> An int written once from the handler (C's volatile sig_atomic_t).
    integer(c_int), volatile, save :: caught = 0

    interface
        !> C's signal(2) (glibc: BSD semantics, interrupted system calls restart).
        type(c_funptr) function c_signal(signum, handler) bind(C, name='signal')
            import :: c_int, c_funptr
            integer(c_int), value :: signum
            type(c_funptr), value :: handler
        end function c_signal
    end interface

contains

    !> Catch SIGINT and SIGTERM from now on.
    subroutine catch_stop_signals()
        type(c_funptr) :: previous
        previous = c_signal(sigint, c_funloc(on_stop_signal))
        previous = c_signal(sigterm, c_funloc(on_stop_signal))
    end subroutine catch_stop_signals

    !> The handler: record the first signal; the next one of this kind gets the default
    !> action (signal(2) is async-signal-safe).
    subroutine on_stop_signal(signum) bind(C)
        integer(c_int), value :: signum
        type(c_funptr) :: previous
        if (caught == 0) caught = signum
        previous = c_signal(signum, c_null_funptr)   ! SIG_DFL is the null pointer
    end subroutine on_stop_signal

    !> The stop signal received so far, 0 if none.
    integer function stop_signal()
        stop_signal = caught
    end function stop_signal

    !> 'SIGINT', 'SIGTERM' or 'signal N'.
    pure function signal_name(signum) result(name)
        integer, intent(in) :: signum
        character(len=:), allocatable :: name
        character(len=12) :: number
        select case (signum)
        case (sigint)
            name = 'SIGINT'
        case (sigterm)
            name = 'SIGTERM'
        case default
            write (number, '(i0)') signum
            name = 'signal '//trim(number)
        end select
    end function signal_name

    !> The error of a run stopped by the signal received; `where` says where it stopped.
    !> Its category gives the exit status 128 + signal (130 SIGINT, 143 SIGTERM).
    subroutine stop_error(error, where)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: where
        integer :: signum
        signum = stop_signal()
        call fatal_error(error, 'stopped by '//signal_name(signum)//' '//where, &
                         merge(interrupt_error, terminate_error, signum == sigint))
    end subroutine stop_error
end module cfrd_signals
