!> Tests of analysis_verification (placeholder until its suite lands).
module test_analysis_verification
    use cfrd_testing, only: unittest_t
    implicit none
    private
    public :: collect_analysis_verification
contains
    subroutine collect_analysis_verification(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        allocate (tests(0))
    end subroutine collect_analysis_verification
end module test_analysis_verification
