!> Tests of io_results (placeholder until its suite lands).
module test_io_results
    use cfrd_testing, only: unittest_t
    implicit none
    private
    public :: collect_io_results
contains
    subroutine collect_io_results(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        allocate (tests(0))
    end subroutine collect_io_results
end module test_io_results
