!> GMRES with a kept factorisation as its preconditioner (issue 21): Newton's corrections
!> A ddu = r solved to a relative residual of `rtol` with the factorisation the system
!> already holds (that of an earlier iteration's consistent tangent, or the midpoint
!> corrector's tangent) instead of a new numeric factorisation of A. The iterates are
!> Newton's own to that residual; this is not the modified Newton method, whose step is the
!> old matrix's solution (docs/theory.md section 9, "Newton's corrections by GMRES").
!> Right preconditioning, so that the residual GMRES minimises is the true one of A x = b
!> [lit: Saad, Iterative Methods for Sparse Linear Systems, 2nd ed. 2003, alg. 9.5; flexible
!> form, the preconditioned vectors kept, alg. 9.6]; x0 = 0; modified Gram-Schmidt; Givens
!> rotations for the small least-squares problem.
module cfrd_krylov
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_sparse, only: sparse_pattern_t, csc_matvec
    use cfrd_linear_solver, only: linear_solver_t
    implicit none
    private

    public :: gmres_solve

contains

    !> x with |b - A x|_2 <= rtol |b|_2, A = (pattern, values), M^-1 the solves of `solver`'s
    !> kept factorisation, in at most max_iterations GMRES iterations (no restart).
    !> `converged` is false, and x not to be used, when the residual is not reached, or when
    !> the rate of the first iterations says it will not be within max_iterations (then a
    !> factorisation of A costs less than going on). The true residual is checked at the end.
    subroutine gmres_solve(solver, pattern, values, b, x, rtol, max_iterations, converged, &
                           iterations, error)
        class(linear_solver_t), intent(inout) :: solver
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:), b(:), rtol
        integer, intent(in) :: max_iterations
        real(dp), intent(out) :: x(:)
        logical, intent(out) :: converged
        integer, intent(out) :: iterations
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: v(:, :), z(:, :), w(:)
        real(dp) :: h(max_iterations + 1, max_iterations), g(max_iterations + 1)
        real(dp) :: cs(max_iterations), sn(max_iterations), y(max_iterations)
        real(dp) :: beta, target, temp, rate
        integer :: n, i, j, m
        n = pattern%n
        converged = .false.
        iterations = 0
        x(1:n) = 0.0_dp
        beta = norm2(b(1:n))
        if (.not. (beta > 0.0_dp)) then
            converged = beta == 0.0_dp
            return
        end if
        target = rtol*beta
        allocate (v(n, max_iterations + 1), z(n, max_iterations), w(n))
        v(:, 1) = b(1:n)/beta
        g = 0.0_dp
        g(1) = beta
        h = 0.0_dp
        m = 0
        do j = 1, max_iterations
            call solver%solve(pattern, values, v(:, j), z(:, j), error)
            if (allocated(error)) return
            call csc_matvec(pattern, values, z(:, j), w)
            do i = 1, j
                h(i, j) = dot_product(w, v(:, i))
                w = w - h(i, j)*v(:, i)
            end do
            h(j + 1, j) = norm2(w)
            if (h(j + 1, j) > 0.0_dp) v(:, j + 1) = w/h(j + 1, j)
            do i = 1, j - 1
                temp = cs(i)*h(i, j) + sn(i)*h(i + 1, j)
                h(i + 1, j) = -sn(i)*h(i, j) + cs(i)*h(i + 1, j)
                h(i, j) = temp
            end do
            temp = hypot(h(j, j), h(j + 1, j))
            if (.not. (temp > 0.0_dp)) return
            cs(j) = h(j, j)/temp
            sn(j) = h(j + 1, j)/temp
            h(j, j) = temp
            h(j + 1, j) = 0.0_dp
            g(j + 1) = -sn(j)*g(j)
            g(j) = cs(j)*g(j)
            m = j
            iterations = j
            if (abs(g(j + 1)) <= target) exit
            ! The mean rate so far: when it does not reach the target within the iterations
            ! left, a factorisation is cheaper than going on.
            if (j >= 2) then
                rate = (abs(g(j + 1))/beta)**(1.0_dp/j)
                if (rate >= 1.0_dp) return
                if (log(rtol)/log(rate) > real(max_iterations, dp) + 0.5_dp) return
            end if
        end do
        if (.not. (abs(g(m + 1)) <= target)) return
        ! y = H^-1 g (upper triangular), x = Z y
        do i = m, 1, -1
            y(i) = (g(i) - dot_product(h(i, i + 1:m), y(i + 1:m)))/h(i, i)
        end do
        x(1:n) = matmul(z(:, 1:m), y(1:m))
        ! The true residual (the recurrence's may drift from it)
        call csc_matvec(pattern, values, x, w)
        converged = norm2(b(1:n) - w) <= target
    end subroutine gmres_solve

end module cfrd_krylov
