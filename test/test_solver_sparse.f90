!> Tests of solver_sparse (placeholder until its suite lands).
module test_solver_sparse
    use cfrd_testing, only: unittest_t
    implicit none
    private
    public :: collect_solver_sparse
contains
    subroutine collect_solver_sparse(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        allocate (tests(0))
    end subroutine collect_solver_sparse
end module test_solver_sparse
