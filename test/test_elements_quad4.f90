!> Tests of elements_quad4 (placeholder until its suite lands).
module test_elements_quad4
    use cfrd_testing, only: unittest_t
    implicit none
    private
    public :: collect_elements_quad4
contains
    subroutine collect_elements_quad4(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        allocate (tests(0))
    end subroutine collect_elements_quad4
end module test_elements_quad4
