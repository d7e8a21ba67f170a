!> A small test harness in the spirit of test-drive: a test is a subroutine that allocates
!> `error` when it fails; a suite is a list of named tests; `check` compares a value with a
!> reference within a stated tolerance and says both when it fails.
module cfrd_testing
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    implicit none
    private

    public :: unittest_t, test_interface, new_unittest, check, fail, run_suite

    abstract interface
        subroutine test_interface(error)
            import :: error_t
            type(error_t), allocatable, intent(out) :: error
        end subroutine test_interface
    end interface

    type :: unittest_t
        character(len=:), allocatable :: name
        procedure(test_interface), pointer, nopass :: test => null()
    end type unittest_t

    interface check
        module procedure check_real, check_int, check_logical, check_string
    end interface check

contains

    function new_unittest(name, test) result(self)
        character(len=*), intent(in) :: name
        procedure(test_interface) :: test
        type(unittest_t) :: self
        self%name = name
        self%test => test
    end function new_unittest

    subroutine fail(error, message)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: message
        allocate (error)
        error%message = message
    end subroutine fail

    !> Passes when |actual - expected| <= max(abs, rel*|expected|); give at least one of them.
    subroutine check_real(error, actual, expected, message, rel, abs)
        type(error_t), allocatable, intent(out) :: error
        real(dp), intent(in) :: actual, expected
        character(len=*), intent(in) :: message
        real(dp), intent(in), optional :: rel, abs
        real(dp) :: tol
        character(len=200) :: line
        tol = 0.0_dp
        if (present(abs)) tol = max(tol, abs)
        if (present(rel)) tol = max(tol, rel*max(1.0e-300_dp, dabs(expected)))
        if (actual /= actual .or. dabs(actual - expected) > tol) then
            write (line, '(a,es24.16,a,es24.16,a,es10.3,a,es10.3)') ': got ', actual, &
                ', expected ', expected, ', |diff| ', dabs(actual - expected), ' > tol ', tol
            call fail(error, message//trim(line))
        end if
    end subroutine check_real

    subroutine check_int(error, actual, expected, message)
        type(error_t), allocatable, intent(out) :: error
        integer, intent(in) :: actual, expected
        character(len=*), intent(in) :: message
        character(len=80) :: line
        if (actual /= expected) then
            write (line, '(a,i0,a,i0)') ': got ', actual, ', expected ', expected
            call fail(error, message//trim(line))
        end if
    end subroutine check_int

    subroutine check_logical(error, condition, message)
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in) :: condition
        character(len=*), intent(in) :: message
        if (.not. condition) call fail(error, message)
    end subroutine check_logical

    subroutine check_string(error, actual, expected, message)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: actual, expected
        character(len=*), intent(in) :: message
        if (actual /= expected) call fail(error, message//": got '"//actual// &
            "', expected '"//expected//"'")
    end subroutine check_string

    !> Runs the tests of one suite whose name matches `only` (all when blank); counts results.
    subroutine run_suite(suite_name, tests, only, npass, nfail)
        character(len=*), intent(in) :: suite_name
        type(unittest_t), intent(in) :: tests(:)
        character(len=*), intent(in) :: only
        integer, intent(inout) :: npass, nfail
        type(error_t), allocatable :: error
        integer :: i
        do i = 1, size(tests)
            if (len_trim(only) > 0 .and. only /= tests(i)%name) cycle
            call tests(i)%test(error)
            if (allocated(error)) then
                nfail = nfail + 1
                write (*, '(a)') 'FAIL '//suite_name//'/'//tests(i)%name//': '//error%message
                deallocate (error)
            else
                npass = npass + 1
                write (*, '(a)') 'PASS '//suite_name//'/'//tests(i)%name
            end if
        end do
    end subroutine run_suite
end module cfrd_testing
