!> Tests of the sparse pattern, assembly and the UMFPACK binding, against dense references:
!> the dense assembled matrix, LAPACK's dgesv, and a spring chain in closed form.
module test_solver_sparse
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, numerical_error
    use cfrd_testing, only: unittest_t, new_unittest, check, fail
    use cfrd_sparse, only: sparse_pattern_t, build_pattern, assemble_element, csc_matvec
    use cfrd_umfpack, only: umfpack_t, max_update_rank
    use cfrd_blas_threads, only: set_blas_threads
    implicit none
    private

    public :: collect_solver_sparse
    !> LAPACK's dense LU solve, the reference of the sparse solves (also of
    !> test_analysis_increment)
    public :: dgesv

    interface
        subroutine dgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
            import :: dp
            integer, intent(in) :: n, nrhs, lda, ldb
            real(dp), intent(inout) :: a(lda, *), b(ldb, *)
            integer, intent(out) :: ipiv(*), info
        end subroutine dgesv
    end interface

contains

    subroutine collect_solver_sparse(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('pattern_matches_dense_assembly', test_pattern_dense), &
                new_unittest('one_blas_thread', test_blas_threads), &
                new_unittest('matvec_matches_dense', test_matvec), &
                new_unittest('solve_matches_dgesv', test_solve_dgesv), &
                new_unittest('spring_chain_closed_form', test_spring_chain), &
                new_unittest('symbolic_reuse', test_symbolic_reuse), &
                new_unittest('singular_matrix_is_an_error', test_singular), &
                new_unittest('nearly_singular_matrix_is_an_error', test_nearly_singular), &
                new_unittest('rcond_of_diagonal', test_rcond), &
                new_unittest('rcond_of_2x2_by_hand', test_rcond_2x2), &
                new_unittest('quad_grid_matches_dense', test_quad_grid), &
                new_unittest('row_update_matches_dgesv', test_row_update), &
                new_unittest('row_update_declined_beyond_rank', test_row_update_rank), &
                new_unittest('row_update_declined_when_singular', test_row_update_singular), &
                new_unittest('row_update_of_the_factorised_matrix', test_row_update_none), &
                new_unittest('row_update_refused_when_not_finite', test_row_update_nan), &
                new_unittest('row_update_refused_when_w_overflows', test_row_update_inf), &
                new_unittest('set_aside_taken_back_for_its_matrix', test_set_aside) &
                ]
    end subroutine collect_solver_sparse

    !> Four elements of different sizes on 6 equations, with prescribed dofs (0) mixed in:
    !> element 1 (3 dofs) 1 2 0, element 2 (4 dofs) 2 3 0 4, element 3 (2 dofs) 5 6, element 4
    !> (2 dofs) 4 6.
    subroutine small_system(dof_ptr, dofs, kes)
        integer, allocatable, intent(out) :: dof_ptr(:), dofs(:)
        real(dp), allocatable, intent(out) :: kes(:)   ! all element matrices, column-major
        integer :: e, m, i, j, q
        dof_ptr = [1, 4, 8, 10, 12]
        dofs = [1, 2, 0, 2, 3, 0, 4, 5, 6, 4, 6]
        allocate (kes(9 + 16 + 4 + 4))
        q = 0
        do e = 1, 4
            m = dof_ptr(e + 1) - dof_ptr(e)
            do j = 1, m
                do i = 1, m
                    q = q + 1
                    ! Symmetric, diagonally dominant: SPD element blocks.
                    if (i == j) then
                        kes(q) = 10.0_dp + e + i
                    else
                        kes(q) = 1.0_dp/(e + i + j)
                    end if
                end do
            end do
        end do
    end subroutine small_system

    subroutine assemble_both(pattern, values, dense, error)
        type(sparse_pattern_t), intent(out) :: pattern
        real(dp), allocatable, intent(out) :: values(:), dense(:, :)
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: dof_ptr(:), dofs(:)
        real(dp), allocatable :: kes(:)
        integer :: e, m, i, j, q, off
        call small_system(dof_ptr, dofs, kes)
        call build_pattern(pattern, 6, dof_ptr, dofs, error)
        if (allocated(error)) return
        allocate (values(pattern%nnz), source=0.0_dp)
        allocate (dense(6, 6), source=0.0_dp)
        off = 0
        do e = 1, 4
            m = dof_ptr(e + 1) - dof_ptr(e)
            call assemble_element(pattern, values, e, reshape(kes(off + 1:off + m*m), [m, m]))
            q = off
            do j = 1, m
                do i = 1, m
                    q = q + 1
                    associate (r => dofs(dof_ptr(e) + i - 1), c => dofs(dof_ptr(e) + j - 1))
                        if (r > 0 .and. c > 0) dense(r, c) = dense(r, c) + kes(q)
                    end associate
                end do
            end do
            off = off + m*m
        end do
    end subroutine assemble_both

    !> Every entry of the sparse matrix equals the dense assembly; the pattern holds exactly
    !> the structurally non-zero entries.
    subroutine test_pattern_dense(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        real(dp), allocatable :: values(:), dense(:, :), rebuilt(:, :)
        integer :: j, p, count
        call assemble_both(pattern, values, dense, error)
        if (allocated(error)) return
        allocate (rebuilt(6, 6), source=0.0_dp)
        do j = 1, 6
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                rebuilt(pattern%rowind(p) + 1, j) = values(p)
            end do
        end do
        call check(error, maxval(abs(rebuilt - dense)), 0.0_dp, 'entries', abs=0.0_dp)
        if (allocated(error)) return
        count = count_nonzero(dense)
        call check(error, pattern%nnz, count, 'stored entries = structural non-zeros')
        if (allocated(error)) return
        call check(error, unsorted_columns(pattern), 0, 'columns with unsorted rows')
    end subroutine test_pattern_dense

    !> Columns of the pattern whose row indices are not strictly increasing (UMFPACK's input
    !> rule) or out of range.
    integer function unsorted_columns(pattern) result(count)
        type(sparse_pattern_t), intent(in) :: pattern
        integer :: j, p
        count = 0
        do j = 1, pattern%n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                if (pattern%rowind(p) < 0 .or. pattern%rowind(p) >= pattern%n) then
                    count = count + 1
                    exit
                end if
                if (p == pattern%colptr(j) + 1) cycle
                if (pattern%rowind(p) <= pattern%rowind(p - 1)) then
                    count = count + 1
                    exit
                end if
            end do
        end do
    end function unsorted_columns

    integer function count_nonzero(a)
        real(dp), intent(in) :: a(:, :)
        count_nonzero = count(a /= 0.0_dp)
    end function count_nonzero

    subroutine test_matvec(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        real(dp), allocatable :: values(:), dense(:, :)
        real(dp) :: x(6), y(6)
        call assemble_both(pattern, values, dense, error)
        if (allocated(error)) return
        x = [1.0_dp, -2.0_dp, 0.5_dp, 3.0_dp, -1.0_dp, 0.25_dp]
        call csc_matvec(pattern, values, x, y)
        call check(error, maxval(abs(y - matmul(dense, x))), 0.0_dp, 'A x', &
                   abs=1e-14_dp*maxval(abs(y)))
    end subroutine test_matvec

    subroutine test_solve_dgesv(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:), dense(:, :)
        real(dp) :: b(6), x(6), reference(6, 1)
        integer :: ipiv(6), info
        call assemble_both(pattern, values, dense, error)
        if (allocated(error)) return
        b = [1.0_dp, 2.0_dp, 3.0_dp, 4.0_dp, 5.0_dp, 6.0_dp]
        call solver%factorise(pattern, values, error)
        if (allocated(error)) return
        call solver%solve(pattern, values, b, x, error)
        if (allocated(error)) return
        reference(:, 1) = b
        call dgesv(6, 1, dense, 6, ipiv, reference, 6, info)
        call check(error, info, 0, 'dgesv info')
        if (allocated(error)) return
        call check(error, maxval(abs(x - reference(:, 1))), 0.0_dp, 'x against dgesv', &
                   abs=1e-12_dp*maxval(abs(reference)))
    end subroutine test_solve_dgesv

    !> n springs of stiffness k in a chain, fixed at one end, force F at the other: node i
    !> moves i F / k (each spring carries F).
    subroutine chain(n, k, pattern, values, error, weak_spring)
        integer, intent(in) :: n
        real(dp), intent(in) :: k
        type(sparse_pattern_t), intent(out) :: pattern
        real(dp), allocatable, intent(out) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        real(dp), intent(in), optional :: weak_spring   ! stiffness of spring 1 if present
        integer, allocatable :: dof_ptr(:), dofs(:)
        real(dp) :: ks
        integer :: e
        allocate (dof_ptr(n + 1), dofs(2*n))
        do e = 1, n
            dof_ptr(e) = 2*e - 1
            dofs(2*e - 1:2*e) = [e - 1, e]     ! equation 0 is the fixed end
        end do
        dof_ptr(n + 1) = 2*n + 1
        call build_pattern(pattern, n, dof_ptr, dofs, error)
        if (allocated(error)) return
        allocate (values(pattern%nnz), source=0.0_dp)
        do e = 1, n
            ks = k
            if (e == 1 .and. present(weak_spring)) ks = weak_spring
            call assemble_element(pattern, values, e, &
                                  ks*reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2]))
        end do
    end subroutine chain

    subroutine test_spring_chain(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:), b(:), x(:)
        real(dp), parameter :: k = 250.0_dp, force = 10.0_dp
        integer, parameter :: n = 50
        integer :: i
        call chain(n, k, pattern, values, error)
        if (allocated(error)) return
        allocate (b(n), source=0.0_dp, x(n))
        b(n) = force
        call solver%factorise(pattern, values, error)
        if (allocated(error)) return
        call solver%solve(pattern, values, b, x, error)
        if (allocated(error)) return
        do i = 1, n
            call check(error, x(i), i*force/k, 'displacement of a chain node', rel=1e-12_dp)
            if (allocated(error)) return
        end do
    end subroutine test_spring_chain

    !> Factorise, change the values on the same pattern, factorise again without a new
    !> symbolic analysis: the answer is that of the new matrix (dgesv).
    subroutine test_symbolic_reuse(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:), dense(:, :)
        real(dp) :: b(6), x(6), reference(6, 1)
        integer :: ipiv(6), info, j, p
        call assemble_both(pattern, values, dense, error)
        if (allocated(error)) return
        call solver%analyse(pattern, values, error)
        if (allocated(error)) return
        call solver%factorise(pattern, values, error)
        if (allocated(error)) return
        values = 2.0_dp*values
        do j = 1, 6
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                if (pattern%rowind(p) + 1 == j) values(p) = values(p) + j
            end do
        end do
        dense = 2.0_dp*dense
        do j = 1, 6
            dense(j, j) = dense(j, j) + j
        end do
        call solver%factorise(pattern, values, error)
        if (allocated(error)) return
        b = [6.0_dp, 5.0_dp, 4.0_dp, 3.0_dp, 2.0_dp, 1.0_dp]
        call solver%solve(pattern, values, b, x, error)
        if (allocated(error)) return
        reference(:, 1) = b
        call dgesv(6, 1, dense, 6, ipiv, reference, 6, info)
        call check(error, maxval(abs(x - reference(:, 1))), 0.0_dp, 'x after refactorisation', &
                   abs=1e-12_dp*maxval(abs(reference)))
    end subroutine test_symbolic_reuse

    subroutine expect_singular(solver, pattern, values, error)
        type(umfpack_t), intent(inout) :: solver
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        call solver%factorise(pattern, values, error)
        if (.not. allocated(error)) then
            call fail(error, 'a singular matrix was factorised without an error')
            return
        end if
        if (error%category /= numerical_error .or. index(error%message, 'singular') == 0) then
            error%message = 'unexpected error: '//error%message
            return
        end if
        deallocate (error)
    end subroutine expect_singular

    !> A chain without its support: the rigid translation makes K singular.
    subroutine test_singular(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:)
        integer :: dofs(8), e
        dofs = [(e, e + 1, e=1, 4)]
        call build_pattern(pattern, 5, [1, 3, 5, 7, 9], dofs, error)
        if (allocated(error)) return
        allocate (values(pattern%nnz), source=0.0_dp)
        do e = 1, 4
            call assemble_element(pattern, values, e, &
                                  reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2]))
        end do
        call expect_singular(solver, pattern, values, error)
    end subroutine test_singular

    !> A chain hanging on a spring 1e-20 times as stiff as the others.
    subroutine test_nearly_singular(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:)
        call chain(5, 1.0_dp, pattern, values, error, weak_spring=1.0e-20_dp)
        if (allocated(error)) return
        call expect_singular(solver, pattern, values, error)
    end subroutine test_nearly_singular

    !> UMFPACK's estimate is min |U_ii| / max |U_ii| of the row-scaled matrix (by default each
    !> row is divided by the sum of its magnitudes, UMFPACK_SCALE_SUM): a diagonal matrix
    !> scales to the identity, so diag(1, 4) has rcond exactly 1 (UMFPACK user guide, Info).
    subroutine test_rcond(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:)
        call build_pattern(pattern, 2, [1, 2, 3], [1, 2], error)
        if (allocated(error)) return
        allocate (values(pattern%nnz), source=0.0_dp)
        call assemble_element(pattern, values, 1, reshape([1.0_dp], [1, 1]))
        call assemble_element(pattern, values, 2, reshape([4.0_dp], [1, 1]))
        call solver%factorise(pattern, values, error)
        if (allocated(error)) return
        call check(error, solver%rcond(), 1.0_dp, 'rcond', rel=1e-14_dp)
    end subroutine test_rcond

    !> [[2, 1], [1, 2]] by hand: the row sums scale it to [[2, 1], [1, 2]]/3; LU with the
    !> diagonal pivots (also the partial-pivoting choice) gives U11 = 2/3 and
    !> U22 = 2/3 - (1/3)(1/3)/(2/3) = 1/2, so rcond = (1/2)/(2/3) = 3/4.
    subroutine test_rcond_2x2(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:)
        call build_pattern(pattern, 2, [1, 3], [1, 2], error)
        if (allocated(error)) return
        allocate (values(pattern%nnz), source=0.0_dp)
        call assemble_element(pattern, values, 1, reshape([2.0_dp, 1.0_dp, 1.0_dp, 2.0_dp], &
                                                          [2, 2]))
        call solver%factorise(pattern, values, error)
        if (allocated(error)) return
        call check(error, solver%rcond(), 0.75_dp, 'rcond', rel=1e-14_dp)
    end subroutine test_rcond_2x2

    !> A 5 x 4 grid of 8-dof quads with the bottom row of nodes fixed, plus 2-dof springs
    !> between neighbouring top nodes (elements of two sizes, up to four per column), with
    !> symmetric positive definite element matrices G^T G + I (G filled from a sine table):
    !> every entry equals the dense assembly exactly (same additions in the same order), the
    !> stored entries are exactly the structural ones, and the solve matches dgesv.
    subroutine test_quad_grid(error)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: nx = 5, ny = 4, nquad = nx*ny, nspring = nx
        integer, parameter :: nelem = nquad + nspring
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        integer :: eq(2, (nx + 1)*(ny + 1)), dof_ptr(nelem + 1), dofs(8*nquad + 2*nspring)
        integer :: n, i, j, e, node(4), m, r, c, a
        integer, allocatable :: ipiv(:)
        real(dp), allocatable :: values(:), dense(:, :), b(:), x(:), reference(:, :)
        logical, allocatable :: structural(:, :)
        real(dp) :: g(8, 8), ke(8, 8)
        integer :: info

        n = 0
        do j = 0, ny
            do i = 0, nx
                if (j == 0) then
                    eq(:, j*(nx + 1) + i + 1) = 0
                else
                    eq(:, j*(nx + 1) + i + 1) = [n + 1, n + 2]
                    n = n + 2
                end if
            end do
        end do
        dof_ptr(1) = 1
        e = 0
        do j = 0, ny - 1
            do i = 0, nx - 1
                e = e + 1
                node = [j*(nx + 1) + i + 1, j*(nx + 1) + i + 2, (j + 1)*(nx + 1) + i + 2, &
                        (j + 1)*(nx + 1) + i + 1]
                dofs(dof_ptr(e):dof_ptr(e) + 7) = reshape(eq(:, node), [8])
                dof_ptr(e + 1) = dof_ptr(e) + 8
            end do
        end do
        do i = 0, nx - 1   ! horizontal springs along the top row
            e = e + 1
            dofs(dof_ptr(e):dof_ptr(e) + 1) = [eq(1, ny*(nx + 1) + i + 1), &
                                                eq(1, ny*(nx + 1) + i + 2)]
            dof_ptr(e + 1) = dof_ptr(e) + 2
        end do

        call build_pattern(pattern, n, dof_ptr, dofs, error)
        if (allocated(error)) return
        allocate (values(pattern%nnz), source=0.0_dp)
        allocate (dense(n, n), source=0.0_dp)
        allocate (structural(n, n), source=.false.)
        do e = 1, nelem
            m = dof_ptr(e + 1) - dof_ptr(e)
            do j = 1, m
                do i = 1, m
                    g(i, j) = sin(real(7*e + 3*i + 11*j, dp))
                end do
            end do
            ke(:m, :m) = matmul(transpose(g(:m, :m)), g(:m, :m))
            do a = 1, m
                ke(a, a) = ke(a, a) + 1.0_dp
            end do
            call assemble_element(pattern, values, e, ke(:m, :m))
            do j = 1, m
                c = dofs(dof_ptr(e) + j - 1)
                if (c <= 0) cycle
                do i = 1, m
                    r = dofs(dof_ptr(e) + i - 1)
                    if (r <= 0) cycle
                    dense(r, c) = dense(r, c) + ke(i, j)
                    structural(r, c) = .true.
                end do
            end do
        end do

        call check(error, pattern%nnz, count(structural), 'stored entries = structural ones')
        if (allocated(error)) return
        call check(error, unsorted_columns(pattern), 0, 'columns with unsorted rows')
        if (allocated(error)) return
        call check(error, maxval(abs(to_dense(pattern, values) - dense)), 0.0_dp, &
                   'entries against the dense assembly', abs=0.0_dp)
        if (allocated(error)) return

        allocate (b(n), x(n), reference(n, 1), ipiv(n))
        do i = 1, n
            b(i) = cos(real(i, dp))
        end do
        call solver%factorise(pattern, values, error)
        if (allocated(error)) return
        call solver%solve(pattern, values, b, x, error)
        if (allocated(error)) return
        reference(:, 1) = b
        call dgesv(n, 1, dense, n, ipiv, reference, n, info)
        call check(error, info, 0, 'dgesv info')
        if (allocated(error)) return
        call check(error, maxval(abs(x - reference(:, 1))), 0.0_dp, 'x against dgesv', &
                   abs=1e-12_dp*maxval(abs(reference)))
    end subroutine test_quad_grid

    !> A saddle-point system like contact's: a chain of nspring springs (stiffness k, the
    !> first end fixed) and ncon multipliers, multiplier c tying dofs c and c + 10 (its
    !> column carries the forces +-k on them); its row is the constraint k (u_c - u_c+10) = 0
    !> when `closed(c)`, else k lambda_c = 0 (open).
    subroutine saddle_system(closed, pattern, values, error)
        logical, intent(in) :: closed(:)
        type(sparse_pattern_t), intent(inout) :: pattern
        real(dp), allocatable, intent(inout) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: nspring = 60
        real(dp), parameter :: k = 250.0_dp
        integer, allocatable :: dof_ptr(:), dofs(:)
        real(dp) :: ke(3, 3)
        integer :: e, c, ncon
        ncon = size(closed)
        if (pattern%n == 0) then
            allocate (dof_ptr(nspring + ncon + 1), dofs(2*nspring + 3*ncon))
            do e = 1, nspring
                dof_ptr(e) = 2*e - 1
                dofs(2*e - 1:2*e) = [e - 1, e]
            end do
            do c = 1, ncon
                dof_ptr(nspring + c) = 2*nspring + 3*c - 2
                dofs(2*nspring + 3*c - 2:2*nspring + 3*c) = [c, c + 10, nspring + c]
            end do
            dof_ptr(nspring + ncon + 1) = size(dofs) + 1
            call build_pattern(pattern, nspring + ncon, dof_ptr, dofs, error)
            if (allocated(error)) return
        end if
        if (allocated(values)) deallocate (values)
        allocate (values(pattern%nnz), source=0.0_dp)
        do e = 1, nspring
            call assemble_element(pattern, values, e, &
                                  k*reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2]))
        end do
        do c = 1, ncon
            ke = 0.0_dp
            ke(1:2, 3) = [k, -k]
            if (closed(c)) then
                ke(3, 1:2) = [k, -k]
            else
                ke(3, 3) = k
            end if
            call assemble_element(pattern, values, nspring + c, ke)
        end do
    end subroutine saddle_system

    !> x of the updated solver against dgesv of the dense matrix, for the load b(i) = cos(i).
    subroutine check_against_dgesv(solver, pattern, values, what, error)
        type(umfpack_t), intent(inout) :: solver
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        character(len=*), intent(in) :: what
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: dense(:, :), b(:), x(:), reference(:, :)
        integer, allocatable :: ipiv(:)
        integer :: i, info
        allocate (b(pattern%n), x(pattern%n), reference(pattern%n, 1), ipiv(pattern%n))
        do i = 1, pattern%n
            b(i) = cos(real(i, dp))
        end do
        call solver%solve(pattern, values, b, x, error)
        if (allocated(error)) return
        dense = to_dense(pattern, values)
        reference(:, 1) = b
        call dgesv(pattern%n, 1, dense, pattern%n, ipiv, reference, pattern%n, info)
        call check(error, info, 0, 'dgesv info')
        if (allocated(error)) return
        call check(error, maxval(abs(x - reference(:, 1))), 0.0_dp, what, &
                   abs=1e-12_dp*maxval(abs(reference)))
    end subroutine check_against_dgesv

    !> Factorise with every multiplier open, then close some, open one again, close more
    !> (the active-set iteration's changes): each updated solve equals dgesv of the changed
    !> matrix to 1e-12, without a new factorisation.
    subroutine test_row_update(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:)
        logical :: closed(40), done
        closed = .false.
        call saddle_system(closed, pattern, values, error)
        if (allocated(error)) return
        call solver%factorise(pattern, values, error)
        if (allocated(error)) return
        call check_against_dgesv(solver, pattern, values, 'x of the factorised matrix', error)
        if (allocated(error)) return
        closed([3, 17]) = .true.
        call update_and_check('x after closing 2 (rank 2)')
        if (allocated(error)) return
        closed([3, 25, 26, 40]) = [.false., .true., .true., .true.]
        call update_and_check('x after opening 1, closing 3 (rank 5)')
        if (allocated(error)) return
        closed(5:14) = .true.
        call update_and_check('x after closing 10 more (rank 15)')
    contains
        subroutine update_and_check(what)
            character(len=*), intent(in) :: what
            call saddle_system(closed, pattern, values, error)
            if (allocated(error)) return
            call solver%update_rows(pattern, values, done, error)
            if (allocated(error)) return
            call check(error, done, 'update done: '//what)
            if (allocated(error)) return
            call check(error, solver%is_updated(), 'solver updated: '//what)
            if (allocated(error)) return
            call check_against_dgesv(solver, pattern, values, what, error)
        end subroutine update_and_check
    end subroutine test_row_update

    !> The retry of a rejected increment (cfrd_increment): A0 factorised and updated (the
    !> predictor's active-set iterations), set aside, A1 factorised (the midpoint's), then
    !> A0 again: taken back, not factorised (reused), its solve the same bits as the first
    !> factorisation's and dgesv's of A0 to 1e-12; a matrix that differs from the one set
    !> aside in one value is factorised anew (not reused), its solve dgesv's.
    subroutine test_set_aside(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:), a0(:), b(:), x_first(:), x_again(:)
        logical :: closed(40), done, reused
        integer :: i
        closed = .false.
        closed(1:20) = .true.
        call saddle_system(closed, pattern, values, error)
        if (allocated(error)) return
        a0 = values
        allocate (b(pattern%n), x_first(pattern%n), x_again(pattern%n))
        do i = 1, pattern%n
            b(i) = cos(real(i, dp))
        end do
        call solver%factorise(pattern, a0, error, reused)
        if (allocated(error)) return
        call check(error, .not. reused, 'the first factorisation is not a reuse')
        if (allocated(error)) return
        call solver%solve(pattern, a0, b, x_first, error)
        if (allocated(error)) return
        closed(30:33) = .true.
        call saddle_system(closed, pattern, values, error)
        if (allocated(error)) return
        call solver%update_rows(pattern, values, done, error)
        if (allocated(error)) return
        call check(error, done, 'the predictor''s update done')
        if (allocated(error)) return
        call solver%set_aside()
        closed(1:10) = .false.
        call saddle_system(closed, pattern, values, error)
        if (allocated(error)) return
        call solver%factorise(pattern, values, error, reused)
        if (allocated(error)) return
        call check(error, .not. reused, 'A1 is not the matrix set aside')
        if (allocated(error)) return
        call check_against_dgesv(solver, pattern, values, 'x of A1', error)
        if (allocated(error)) return
        call solver%factorise(pattern, a0, error, reused)
        if (allocated(error)) return
        call check(error, reused, 'A0 again: the factorisation set aside taken back')
        if (allocated(error)) return
        call check(error, .not. solver%is_updated(), 'taken back without the update')
        if (allocated(error)) return
        call solver%solve(pattern, a0, b, x_again, error)
        if (allocated(error)) return
        call check(error, maxval(abs(x_again - x_first)), 0.0_dp, &
                   'x of A0 taken back against its first factorisation (bit for bit)')
        if (allocated(error)) return
        call check_against_dgesv(solver, pattern, a0, 'x of A0 taken back', error)
        if (allocated(error)) return
        ! set aside again, then a matrix one value away from A0: factorised, not reused
        call solver%set_aside()
        values = a0
        values(1) = values(1)*(1.0_dp + 1.0e-15_dp)
        call solver%factorise(pattern, values, error, reused)
        if (allocated(error)) return
        call check(error, .not. reused, 'a matrix one value off A0 is factorised anew')
        if (allocated(error)) return
        call check_against_dgesv(solver, pattern, values, 'x of A0 one value off', error)
    end subroutine test_set_aside

    !> More rows changed than max_update_rank: the update is declined (the caller
    !> factorises), and the solves are still those of the factorised matrix.
    subroutine test_row_update_rank(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:), original(:)
        logical :: closed(40), done
        closed = .false.
        call saddle_system(closed, pattern, values, error)
        if (allocated(error)) return
        call solver%factorise(pattern, values, error)
        if (allocated(error)) return
        original = values
        closed(1:max_update_rank + 1) = .true.
        call saddle_system(closed, pattern, values, error)
        if (allocated(error)) return
        call solver%update_rows(pattern, values, done, error)
        if (allocated(error)) return
        call check(error, .not. done, 'update of max_update_rank + 1 rows declined')
        if (allocated(error)) return
        call check_against_dgesv(solver, pattern, original, 'x of the factorised matrix', error)
    end subroutine test_row_update_rank

    !> A changed row of zeros (an open row with no diagonal) makes the matrix singular: the
    !> capacitance matrix is singular too and the update declined, so that the factorisation
    !> reports the singularity as for any other matrix.
    subroutine test_row_update_singular(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:)
        logical :: closed(40), done
        closed = .false.
        call factorised_saddle(closed, pattern, values, solver, error)
        if (allocated(error)) return
        call set_row(pattern, values, 61, 0.0_dp)      ! multiplier 1, all zero
        call solver%update_rows(pattern, values, done, error)
        if (allocated(error)) return
        call check(error, .not. done, 'update to a singular matrix declined')
        if (allocated(error)) return
        call expect_singular(solver, pattern, values, error)
    end subroutine test_row_update_singular

    !> The matrix factorised, unchanged (an increment of a linear model whose contact rows
    !> stay as they were, docs/robustness.md "The empty row update"): no row differs, so the
    !> update is done without a capacitance matrix (an empty one reached LAPACK's dgecon with
    !> the norm -huge, XERBLA's message on standard output, and the same matrix was
    !> factorised again); the solves are the factorisation's own, against dgesv to 1e-12.
    subroutine test_row_update_none(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:)
        logical :: closed(40), done, refused
        closed = .false.
        closed([4, 9]) = .true.
        call factorised_saddle(closed, pattern, values, solver, error)
        if (allocated(error)) return
        call saddle_system(closed, pattern, values, error)
        if (allocated(error)) return
        call solver%update_rows(pattern, values, done, error, refused)
        if (allocated(error)) return
        call check(error, done .and. .not. refused .and. .not. solver%is_updated(), &
                   'the unchanged matrix: update done, not refused, the factors'' own solves')
        if (allocated(error)) return
        call check_against_dgesv(solver, pattern, values, 'x of the unchanged matrix', error)
    end subroutine test_row_update_none

    !> A changed row with a NaN (a contact row built from a non-finite state): the
    !> capacitance matrix is not finite, so the update is refused before LAPACK sees it
    !> (no error: the caller factorises, and the factorisation judges the matrix); the
    !> solves stay those of the factorised matrix (dgesv, 1e-12).
    subroutine test_row_update_nan(error)
        use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:), original(:)
        logical :: closed(40), done, refused
        closed = .false.
        call factorised_saddle(closed, pattern, values, solver, error)
        if (allocated(error)) return
        original = values
        closed(3) = .true.
        call saddle_system(closed, pattern, values, error)
        if (allocated(error)) return
        ! row 63 (multiplier 3), its entry in column 3
        call set_row(pattern, values, 63, ieee_value(1.0_dp, ieee_quiet_nan), 3)
        call solver%update_rows(pattern, values, done, error, refused)
        if (allocated(error)) return
        call check(error, refused .and. .not. done .and. .not. solver%is_updated(), &
                   'an update with a NaN refused')
        if (allocated(error)) return
        call check_against_dgesv(solver, pattern, original, 'x of the factorised matrix', error)
    end subroutine test_row_update_nan

    !> A base solve that overflows: diag(1e-310, 1e-310) is perfectly conditioned (UMFPACK's
    !> rcond 1) but A0^-1 e_1 = 1e310 is Inf in double precision. Changing row 1 needs that
    !> column of w: the update is refused before LAPACK (overflow not halting during the
    !> update, as in the release build; the halting modes and flags restored after).
    subroutine test_row_update_inf(error)
        use, intrinsic :: ieee_arithmetic, only: ieee_get_halting_mode, &
                                                 ieee_set_halting_mode, ieee_set_flag, &
                                                 ieee_overflow, ieee_invalid, ieee_usual, &
                                                 ieee_is_finite
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: tiny_value = 1.0e-310_dp
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:)
        real(dp) :: x(2)
        logical :: done, refused, halting(2)
        call build_pattern(pattern, 2, [1, 2, 3], [1, 2], error)
        if (allocated(error)) return
        allocate (values(pattern%nnz), source=tiny_value)
        call solver%factorise(pattern, values, error)
        if (allocated(error)) return
        call check(error, solver%rcond(), 1.0_dp, 'rcond of diag(1e-310, 1e-310)', rel=1e-12_dp)
        if (allocated(error)) return
        call ieee_get_halting_mode([ieee_overflow, ieee_invalid], halting)
        call ieee_set_halting_mode([ieee_overflow, ieee_invalid], .false.)
        call solver%solve(pattern, values, [1.0_dp, 0.0_dp], x, error)  ! A0^-1 e_1
        if (.not. allocated(error)) then
            values(1) = 2.0_dp*tiny_value
            call solver%update_rows(pattern, values, done, error, refused)
        end if
        call ieee_set_flag(ieee_usual, .false.)
        call ieee_set_halting_mode([ieee_overflow, ieee_invalid], halting)
        if (allocated(error)) return
        call check(error, .not. ieee_is_finite(x(1)), 'A0^-1 e_1 overflows')
        if (allocated(error)) return
        call check(error, refused .and. .not. done .and. .not. solver%is_updated(), &
                   'an update whose column of w overflows refused')
    end subroutine test_row_update_inf

    !> saddle_system(closed), factorised by solver.
    subroutine factorised_saddle(closed, pattern, values, solver, error)
        logical, intent(in) :: closed(:)
        type(sparse_pattern_t), intent(inout) :: pattern
        real(dp), allocatable, intent(inout) :: values(:)
        type(umfpack_t), intent(inout) :: solver
        type(error_t), allocatable, intent(out) :: error
        call saddle_system(closed, pattern, values, error)
        if (allocated(error)) return
        call solver%factorise(pattern, values, error)
    end subroutine factorised_saddle

    !> The stored entries of row `row` (1-based) set to `value`; with `column`, that one only.
    subroutine set_row(pattern, values, row, value, column)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(inout) :: values(:)
        integer, intent(in) :: row
        real(dp), intent(in) :: value
        integer, intent(in), optional :: column
        integer :: j, p
        do j = 1, pattern%n
            if (present(column)) then
                if (j /= column) cycle
            end if
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                if (pattern%rowind(p) == row - 1) values(p) = value
            end do
        end do
    end subroutine set_row

    !> The dense matrix held by a compressed-column pattern and its values.
    function to_dense(pattern, values) result(a)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        real(dp) :: a(pattern%n, pattern%n)
        integer :: j, p
        a = 0.0_dp
        do j = 1, pattern%n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                a(pattern%rowind(p) + 1, j) = values(p)
            end do
        end do
    end function to_dense
    !> A run asks OpenBLAS for one thread (cfrd_blas_threads): OpenBLAS's own count
    !> (openblas_get_num_threads) is 1 afterwards. With the user's OPENBLAS_NUM_THREADS or
    !> CFRD_BLAS_THREADS set, or a BLAS that is not OpenBLAS, the test says so and checks
    !> that nothing was set where nothing should be.
    subroutine test_blas_threads(error)
        use, intrinsic :: iso_c_binding, only: c_int, c_ptr, c_funptr, c_null_ptr, c_char, &
                                               c_null_char, c_associated, c_f_procpointer
        type(error_t), allocatable, intent(out) :: error
        interface
            type(c_funptr) function dlsym(handle, symbol) bind(C, name='dlsym')
                import :: c_ptr, c_funptr, c_char
                type(c_ptr), value :: handle
                character(kind=c_char), intent(in) :: symbol(*)
            end function dlsym
        end interface
        abstract interface
            integer(c_int) function get_threads_t() bind(C)
                import :: c_int
            end function get_threads_t
        end interface
        procedure(get_threads_t), pointer :: get_threads
        type(c_funptr) :: address
        integer :: threads, length_user, length_cfrd, status
        character(len=16) :: value
        call get_environment_variable('OPENBLAS_NUM_THREADS', value, length_user, status)
        call get_environment_variable('CFRD_BLAS_THREADS', value, length_cfrd, status)
        threads = set_blas_threads()
        address = dlsym(c_null_ptr, 'openblas_get_num_threads'//c_null_char)
        if (.not. c_associated(address)) then
            write (*, '(a)') '  the BLAS is not OpenBLAS: nothing to set'
            call check(error, threads == 0, 'set_blas_threads set a count without OpenBLAS')
            return
        end if
        if (length_user > 0 .or. length_cfrd > 0) then
            write (*, '(a)') '  OPENBLAS_NUM_THREADS or CFRD_BLAS_THREADS is set: the user''s'
            return
        end if
        call c_f_procpointer(address, get_threads)
        write (*, '(a,i0,a,i0)') '  set ', threads, ', OpenBLAS reports ', get_threads()
        call check(error, threads == 1 .and. get_threads() == 1, &
                   'one BLAS thread asked for and reported by OpenBLAS')
    end subroutine test_blas_threads

end module test_solver_sparse
