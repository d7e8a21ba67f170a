!> Tests of GMRES with a kept factorisation as its preconditioner (cfrd_krylov), against
!> the closed form: b = A 1, so that the exact solution is the vector of ones. A is an
!> unsymmetric tridiagonal matrix (1-D convection-diffusion, tridiag(-1 - c, 2, -1 + c),
!> condition number about 4e2 for c = 0.2);
!> the preconditioner is UMFPACK's factorisation of the same matrix with another c.
module test_solver_krylov
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_sparse, only: sparse_pattern_t, csc_matvec
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

    !> tridiag(-1 - c, 2, -1 + c) of order n in compressed columns (0-based, as cfrd_sparse).
    subroutine convection(c, pattern, values)
        real(dp), intent(in) :: c
        type(sparse_pattern_t), intent(out) :: pattern
        real(dp), allocatable, intent(out) :: values(:)
        integer :: j, p
        pattern%n = n
        pattern%nnz = 3*n - 2
        allocate (pattern%colptr(n + 1), pattern%rowind(pattern%nnz), values(pattern%nnz))
        p = 0
        do j = 1, n
            pattern%colptr(j) = p
            if (j > 1) call put(j - 1, -1.0_dp + c)
            call put(j, 2.0_dp)
            if (j < n) call put(j + 1, -1.0_dp - c)
        end do
        pattern%colptr(n + 1) = p
    contains
        subroutine put(i, a)
            integer, intent(in) :: i
            real(dp), intent(in) :: a
            p = p + 1
            pattern%rowind(p) = i - 1
            values(p) = a
        end subroutine put
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
        call convection(c0, pattern, a0)
        call convection(c, pattern, a)
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
    !> x = 1 to 1e-9 (the condition number, about 4e2, times the residual).
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
