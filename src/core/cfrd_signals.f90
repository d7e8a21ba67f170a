!> Termination signals: SIGTERM (what Slurm sends at a job's time limit) and SIGINT (Ctrl-C)
!> are noted by a C handler (cfrd_signals.c) and read here, so that the program can stop at
!> the end of the stage it is in and keep the completed stages (app/main.f90).
module cfrd_signals
    use, intrinsic :: iso_c_binding, only: c_int
    implicit none
    private

    public :: catch_termination, termination_signal, signal_name, sigint, sigterm

    integer, parameter :: sigint = 2, sigterm = 15

    interface
        subroutine c_catch_termination() bind(C, name='cfrd_catch_termination')
        end subroutine c_catch_termination

        integer(c_int) function c_termination_signal() bind(C, name='cfrd_termination_signal')
            import :: c_int
        end function c_termination_signal
    end interface

contains

    !> From now on SIGTERM and SIGINT are noted instead of ending the program at once.
    subroutine catch_termination()
        call c_catch_termination()
    end subroutine catch_termination

    !> The signal received so far (sigterm, sigint), or 0.
    integer function termination_signal()
        termination_signal = int(c_termination_signal())
    end function termination_signal

    pure function signal_name(number) result(name)
        integer, intent(in) :: number
        character(len=:), allocatable :: name
        select case (number)
        case (sigterm)
            name = 'SIGTERM'
        case (sigint)
            name = 'SIGINT'
        case default
            name = 'a signal'
        end select
    end function signal_name
end module cfrd_signals
