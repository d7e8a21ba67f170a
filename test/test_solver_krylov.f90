!> Tests of GMRES with a kept factorisation as its preconditioner (cfrd_krylov), against
!> the closed form: b = A 1, so that the exact solution is the vector of ones. A is an
!> unsymmetric tridiagonal matrix (1-D convection-diffusion, tridiag(-1 - c, 2, -1 + c));
!> the preconditioner is UMFPACK's factorisation of the same matrix with another c.
module test_solver_krylov
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_sparse, only: sparse_pattern_t, build_pattern, assemble_element, csc_matvec
    use cfrd_linear_solver, only: linear_solver_t, linear_solver_umfpack
    use cfrd_krylov, only: gmres_solve
    implicit none
    private

    public :: collect_solver_krylov

    integer, parameter :: n = 60

contains

    subroutine collect_solver_krylov(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('gmres_exact_preconditioner', test_exact), &
                new_unittest('gmres_near_preconditioner', test_near), &
                new_unittest('gmres_far_preconditioner_declines', test_far) &
                ]
    end subroutine collect_solver_krylov

    !> The pattern and values of tridiag(-1 - c, 2, -1 + c) of order n (the last diagonal 1),
    !> assembled from n two-node "elements" [1, -1 + c; -1 - c, 1] (node 0 is no equation).
    subroutine convection(c, pattern, values, error)
        real(dp), intent(in) :: c
        type(sparse_pattern_t), intent(out) :: pattern
        real(dp), allocatable, intent(out) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        integer :: dof_ptr(n + 1), dofs(2*n), e
        do e = 1, n
            dof_ptr(e) = 2*e - 1
            dofs(2*e - 1:2*e) = [e - 1, e]
        end do
        dof_ptr(n + 1) = 2*n + 1
        call build_pattern(pattern, n, dof_ptr, dofs, error)
        if (allocated(error)) return
        allocate (values(pattern%nnz), source=0.0_dp)
        do e = 1, n
            call assemble_element(pattern, values, e, &
                                  reshape([1.0_dp, -1.0_dp - c, -1.0_dp + c, 1.0_dp], [2, 2]))
        end do
    end subroutine convection

    !> GMRES on A (c) preconditioned by UMFPACK's factors of A (c0), b = A 1.
    subroutine run(c, c0, max_iterations, x, converged, iterations, residual, error)
        real(dp), intent(in) :: c, c0
        integer, intent(in) :: max_iterations
        real(dp), allocatable, intent(out) :: x(:)
        logical, intent(out) :: converged
        integer, intent(out) :: iterations
        real(dp), intent(out) :: residual
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: a(:), a0(:), b(:), ax(:)
        real(dp) :: ones(n)
        logical :: declined
        call convection(c0, pattern, a0, error)
        if (allocated(error)) return
        call convection(c, pattern, a, error)
        if (allocated(error)) return
        call solver%configure(linear_solver_umfpack, .false.)
        call solver%choose(pattern, a0, error)
        if (allocated(error)) return
        call solver%analyse(pattern, a0, error)
        if (allocated(error)) return
        call solver%factorise(pattern, a0, declined, error)
        if (allocated(error)) return
        call solver%set_refinement(.false.)
        ones = 1.0_dp
        allocate (b(n), ax(n), x(n))
        call csc_matvec(pattern, a, ones, b)
        call gmres_solve(solver, pattern, a, b, x, 1.0e-12_dp, max_iterations, converged, &
                         iterations, error)
        if (allocated(error)) return
        call csc_matvec(pattern, a, x, ax)
        residual = norm2(b - ax)/norm2(b)
        call solver%release()
    end subroutine run

    !> The preconditioner is A's own factorisation: one iteration, x = 1.
    subroutine test_exact(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: x(:)
        real(dp) :: residual
        integer :: iterations
        logical :: converged
        call run(0.2_dp, 0.2_dp, 10, x, converged, iterations, residual, error)
        if (allocated(error)) return
        call check(error, converged, 'GMRES did not converge with the exact factorisation')
        if (allocated(error)) return
        call check(error, iterations, 1, 'iterations with the exact factorisation')
        if (allocated(error)) return
        call check(error, maxval(abs(x - 1.0_dp)) <= 1.0e-12_dp, 'x is not 1')
    end subroutine test_exact

    !> A nearby matrix's factorisation (c 0.2 against 0.201): converged to the relative
    !> residual 1e-12 (checked here again on the returned x) in fewer than 10 iterations,
    !> x = 1 to 1e-9 (the matrix's condition number, about 1e3, times the residual).
    subroutine test_near(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: x(:)
        real(dp) :: residual
        integer :: iterations
        logical :: converged
        call run(0.2_dp, 0.201_dp, 10, x, converged, iterations, residual, error)
        if (allocated(error)) return
        write (*, '(a,i3,a,es10.2,a,es10.2)') '  iterations', iterations, ', residual', &
            residual, ', max |x - 1|', maxval(abs(x - 1.0_dp))
        call check(error, converged, 'GMRES did not converge with a nearby factorisation')
        if (allocated(error)) return
        call check(error, iterations > 1 .and. iterations < 10, 'iterations out of range')
        if (allocated(error)) return
        call check(error, residual <= 1.0e-12_dp, 'relative residual above 1e-12')
        if (allocated(error)) return
        call check(error, maxval(abs(x - 1.0_dp)) <= 1.0e-9_dp, 'x is not 1')
    end subroutine test_near

    !> A far matrix's factorisation (the opposite convection, c -0.9 against 0.9) with at
    !> most 3 iterations: GMRES declines (converged false) instead of returning a poor x.
    subroutine test_far(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: x(:)
        real(dp) :: residual
        integer :: iterations
        logical :: converged
        call run(0.9_dp, -0.9_dp, 3, x, converged, iterations, residual, error)
        if (allocated(error)) return
        call check(error, .not. converged, 'GMRES claims convergence with a far preconditioner')
    end subroutine test_far

end module test_solver_krylov
