!> Error handling in the style of fpm: a routine that can fail ends with
!> `type(error_t), allocatable, intent(out) :: error`; the caller tests `allocated(error)`.
!> Only the program in `app/` turns an error into an exit status.
module cfrd_error
    implicit none
    private

    public :: error_t, input_error, numerical_error, usage_error, io_error
    public :: interrupt_error, terminate_error
    public :: fatal_error, error_status

    !> Category codes; `error_status` maps them to the documented exit statuses.
    integer, parameter :: input_error = 2      !! bad deck: exit status 2
    integer, parameter :: usage_error = 3      !! bad command line: exit status 2
    integer, parameter :: numerical_error = 1  !! singular matrix, no convergence: exit status 1
    integer, parameter :: io_error = 4         !! cannot write a result file: exit status 1
    !> Stopped by a signal: exit status 128 + signal, the shells' convention
    integer, parameter :: interrupt_error = 5  !! SIGINT (Ctrl-C): exit status 130
    integer, parameter :: terminate_error = 6  !! SIGTERM (Slurm's time limit): exit status 143

    !> One error: what category, and a message that says where and why.
    type :: error_t
        integer :: category = input_error
        character(len=:), allocatable :: message
    end type error_t

contains

    !> Allocate `error` with a message and a category (default: input error).
    pure subroutine fatal_error(error, message, category)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: message
        integer, intent(in), optional :: category
        allocate (error)
        error%message = message
        if (present(category)) error%category = category
    end subroutine fatal_error

    !> Exit status documented for the command line: 2 bad input or usage, 130 / 143 stopped
    !> by SIGINT / SIGTERM, 1 otherwise.
    pure integer function error_status(error)
        type(error_t), intent(in) :: error
        select case (error%category)
        case (input_error, usage_error)
            error_status = 2
        case (interrupt_error)
            error_status = 130
        case (terminate_error)
            error_status = 143
        case default
            error_status = 1
        end select
    end function error_status
end module cfrd_error
