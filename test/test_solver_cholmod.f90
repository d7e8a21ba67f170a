!> Tests of the CHOLMOD binding and the choice between CHOLMOD and UMFPACK
!> (cfrd_cholmod, cfrd_linear_solver, cfrd_linear_system: factorise_values), against closed
!> forms: a bar under a uniform axial load (symmetric positive definite), 2 x 2 blocks of
!> known inverse (indefinite, unsymmetric).
module test_solver_cholmod
    use, intrinsic :: iso_c_binding, only: c_long_long
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_sparse, only: sparse_pattern_t, build_pattern, assemble_element
    use cfrd_cholmod, only: cholmod_t, mirror_positions, symmetric_values, symmetry_tolerance, &
                            ordering_for, ordering_amd, ordering_metis, ordering_nesdis
    use cfrd_linear_solver, only: linear_solver_t, linear_solver_auto, linear_solver_cholmod, &
                                  linear_solver_umfpack
    use cfrd_linear_system, only: system_t, factorise_values
    use cfrd_results, only: stage_result_t
    use cfrd_omp_threads, only: regions_in_place
    implicit none
    private

    public :: collect_solver_cholmod

    real(dp), parameter :: bar_length = 10.0_dp, bar_ea = 2.0e6_dp, bar_q = 5.0_dp

contains

    subroutine collect_solver_cholmod(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('bar_closed_form_both_solvers', test_bar_both), &
                new_unittest('mirror_and_symmetry', test_symmetry), &
                new_unittest('indefinite_goes_to_umfpack', test_indefinite), &
                new_unittest('unsymmetric_goes_to_umfpack', test_unsymmetric), &
                new_unittest('forced_cholmod_is_an_error', test_forced), &
                new_unittest('factorise_values_counts', test_counts), &
                new_unittest('bar_each_ordering', test_orderings), &
                new_unittest('ordering_by_what_pays', test_ordering_rule), &
                new_unittest('kept_analysis_copied', test_kept_copy), &
                new_unittest('regions_run_in_place', test_regions_in_place) &
                ]
    end subroutine collect_solver_cholmod

    !> A bar of length L fixed at x = 0, axial stiffness EA, uniform axial load q, n linear
    !> elements with consistent nodal loads (q h / 2 per node); the exact solution is
    !> u(x) = q (L x - x^2 / 2) / EA, and in 1-D linear elements with consistent loads are
    !> exact at the nodes (Tong 1969; docs/theory.md section 7, the confined column): the
    !> reference. Equation i is node i (node 0 is fixed).
    subroutine bar(n, pattern, values, b, exact, error)
        integer, intent(in) :: n
        type(sparse_pattern_t), intent(out) :: pattern
        real(dp), allocatable, intent(out) :: values(:), b(:), exact(:)
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: dof_ptr(:), dofs(:)
        real(dp) :: h, x
        integer :: e, i
        allocate (dof_ptr(n + 1), dofs(2*n))
        do e = 1, n
            dof_ptr(e) = 2*e - 1
            dofs(2*e - 1:2*e) = [e - 1, e]
        end do
        dof_ptr(n + 1) = 2*n + 1
        call build_pattern(pattern, n, dof_ptr, dofs, error)
        if (allocated(error)) return
        h = bar_length/n
        allocate (values(pattern%nnz), source=0.0_dp)
        do e = 1, n
            call assemble_element(pattern, values, e, &
                                  bar_ea/h*reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2]))
        end do
        allocate (b(n), source=bar_q*h)
        b(n) = 0.5_dp*bar_q*h
        allocate (exact(n))
        do i = 1, n
            x = i*h
            exact(i) = bar_q*(bar_length*x - 0.5_dp*x**2)/bar_ea
        end do
    end subroutine bar

    !> m independent 2 x 2 blocks [[a, b], [c, d]] on equations 2k-1, 2k.
    subroutine blocks(m, block, pattern, values, error)
        integer, intent(in) :: m
        real(dp), intent(in) :: block(2, 2)
        type(sparse_pattern_t), intent(out) :: pattern
        real(dp), allocatable, intent(out) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: dof_ptr(:), dofs(:)
        integer :: k
        dof_ptr = [(2*k - 1, k = 1, m + 1)]
        dofs = [(k, k = 1, 2*m)]
        call build_pattern(pattern, 2*m, dof_ptr, dofs, error)
        if (allocated(error)) return
        allocate (values(pattern%nnz), source=0.0_dp)
        do k = 1, m
            call assemble_element(pattern, values, k, block)
        end do
    end subroutine blocks

    !> Factorise (UMFPACK again after CHOLMOD declines, as factorise_values does) and solve.
    subroutine factorise_solve(solver, pattern, values, b, x, declines, error)
        type(linear_solver_t), intent(inout) :: solver
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:), b(:)
        real(dp), intent(out) :: x(:)
        integer, intent(out) :: declines
        type(error_t), allocatable, intent(out) :: error
        logical :: declined
        declines = 0
        call solver%choose(pattern, values, error)
        if (allocated(error)) return
        do
            if (.not. solver%is_analysed()) call solver%analyse(pattern, values, error)
            if (allocated(error)) return
            call solver%factorise(pattern, values, declined, error)
            if (allocated(error)) return
            if (.not. declined) exit
            declines = declines + 1
        end do
        call solver%solve(pattern, values, b, x, error)
    end subroutine factorise_solve

    subroutine test_bar_both(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: values(:), b(:), exact(:), x(:)
        integer :: choice, declines, round
        integer, parameter :: n = 200
        call bar(n, pattern, values, b, exact, error)
        if (allocated(error)) return
        allocate (x(n))
        do choice = linear_solver_auto, linear_solver_umfpack
            call solver%configure(choice, .true.)
            ! twice: the second factorisation reuses the analysis
            do round = 1, 2
                call factorise_solve(solver, pattern, values*round, b, x, declines, error)
                if (allocated(error)) return
                call check(error, solver%is_cholesky() .eqv. (choice /= linear_solver_umfpack), &
                           'CHOLMOD factorised it unless UMFPACK is forced')
                if (allocated(error)) return
                call check(error, declines, 0, 'CHOLMOD declines of an SPD matrix')
                if (allocated(error)) return
                call check(error, maxval(abs(round*x - exact)), 0.0_dp, &
                           'bar under uniform load against u = q (L x - x^2/2) / EA', &
                           abs=1.0e-11_dp*maxval(abs(exact)))
                if (allocated(error)) return
            end do
            call solver%release()
        end do
    end subroutine test_bar_both

    !> CHOLMOD's supernodal factorisation opens OpenMP parallel regions (several per
    !> supernode; cfrd_cholmod runs them on one thread): they run in place, without a team
    !> (cfrd_omp_in_place.c), and the bar's solution is still the closed form.
    subroutine test_regions_in_place(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: values(:), b(:), exact(:), x(:)
        integer :: declines
        integer(c_long_long) :: before
        call bar(400, pattern, values, b, exact, error)
        if (allocated(error)) return
        allocate (x(size(b)))
        call solver%configure(linear_solver_cholmod, .true.)
        before = regions_in_place()
        call factorise_solve(solver, pattern, values, b, x, declines, error)
        if (allocated(error)) return
        call check(error, regions_in_place() > before, &
                   'the factorisation''s parallel regions ran in place')
        if (allocated(error)) return
        call check(error, maxval(abs(x - exact)), 0.0_dp, &
                   'bar under uniform load against u = q (L x - x^2/2) / EA', &
                   abs=1.0e-11_dp*maxval(abs(exact)))
        call solver%release()
    end subroutine test_regions_in_place

    !> The mirror of each entry, and the tolerance: a relative asymmetry below it passes,
    !> one above does not; a missing transpose of a non-zero fails.
    subroutine test_symmetry(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        real(dp), allocatable :: values(:), b(:), exact(:)
        integer, allocatable :: mirror(:)
        integer :: j, p
        call bar(5, pattern, values, b, exact, error)
        if (allocated(error)) return
        mirror = mirror_positions(pattern)
        do j = 1, pattern%n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                if (pattern%rowind(p) + 1 == j) then
                    call check(error, mirror(p), p, 'a diagonal entry is its own mirror')
                else
                    call check(error, pattern%rowind(mirror(p)) + 1, j, 'row of the mirror')
                end if
                if (allocated(error)) return
            end do
        end do
        call check(error, symmetric_values(pattern, values, mirror), 'the bar is symmetric')
        if (allocated(error)) return
        ! entry (2, 1): the bar's diagonal is 2 EA/h, so the bound is 2 EA/h times the tolerance
        p = pattern%colptr(1) + 2
        values(p) = values(p)*(1.0_dp + 0.5_dp*symmetry_tolerance)
        call check(error, symmetric_values(pattern, values, mirror), &
                   'half the tolerance of asymmetry passes')
        if (allocated(error)) return
        values(p) = values(p)*(1.0_dp + 4.0_dp*symmetry_tolerance)
        call check(error, .not. symmetric_values(pattern, values, mirror), &
                   'four times the tolerance does not')
        if (allocated(error)) return
        values(p) = values(mirror(p))
        values(1) = -values(1)
        call check(error, .not. symmetric_values(pattern, values, mirror), &
                   'a negative diagonal does not')
    end subroutine test_symmetry

    !> [[1, 2], [2, 1]] (eigenvalues 3 and -1): symmetric, not positive definite. CHOLMOD
    !> declines it, UMFPACK solves it: x = (1/3, 1/3) for b = (1, 1) by hand.
    subroutine test_indefinite(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: values(:), x(:)
        integer :: declines
        call blocks(3, reshape([1.0_dp, 2.0_dp, 2.0_dp, 1.0_dp], [2, 2]), pattern, values, error)
        if (allocated(error)) return
        allocate (x(6))
        call factorise_solve(solver, pattern, values, [(1.0_dp, declines = 1, 6)], x, &
                             declines, error)
        if (allocated(error)) return
        call check(error, declines, 1, 'CHOLMOD declined the indefinite matrix once')
        if (allocated(error)) return
        call check(error, .not. solver%is_cholesky(), 'UMFPACK factorised it')
        if (allocated(error)) return
        call check(error, maxval(abs(x - 1.0_dp/3.0_dp)), 0.0_dp, &
                   'x = (1/3, 1/3) of each block', abs=1.0e-14_dp)
    end subroutine test_indefinite

    !> [[2, 0.5], [1, 2]] (column-major [2, 1, 0.5, 2]): not symmetric, so not offered to
    !> CHOLMOD at all; b = (2.5, 3) gives x = (1, 1) by hand.
    subroutine test_unsymmetric(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: values(:), x(:)
        integer :: declines, k
        call blocks(2, reshape([2.0_dp, 1.0_dp, 0.5_dp, 2.0_dp], [2, 2]), pattern, values, error)
        if (allocated(error)) return
        allocate (x(4))
        call factorise_solve(solver, pattern, values, [(2.5_dp, 3.0_dp, k = 1, 2)], x, &
                             declines, error)
        if (allocated(error)) return
        call check(error, declines, 0, 'no CHOLMOD attempt')
        if (allocated(error)) return
        call check(error, .not. solver%is_cholesky(), 'UMFPACK factorised it')
        if (allocated(error)) return
        call check(error, maxval(abs(x - 1.0_dp)), 0.0_dp, 'x = (1, 1) of each block', &
                   abs=1.0e-14_dp)
    end subroutine test_unsymmetric

    !> --linear-solver cholmod: an indefinite or unsymmetric matrix is an error naming the
    !> option, not a fallback.
    subroutine test_forced(error)
        type(error_t), allocatable, intent(out) :: error
        type(error_t), allocatable :: failure
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: values(:), x(:)
        integer :: declines, k
        allocate (x(4))
        call blocks(2, reshape([1.0_dp, 2.0_dp, 2.0_dp, 1.0_dp], [2, 2]), pattern, values, error)
        if (allocated(error)) return
        call solver%configure(linear_solver_cholmod, .true.)
        call factorise_solve(solver, pattern, values, [(1.0_dp, k = 1, 4)], x, declines, failure)
        call check(error, allocated(failure), 'indefinite under --linear-solver cholmod fails')
        if (allocated(error)) return
        call check(error, index(failure%message, 'not positive definite') > 0 .and. &
                   index(failure%message, '--linear-solver cholmod') > 0, &
                   'the message says why and names the option: '//failure%message)
        if (allocated(error)) return
        deallocate (failure)
        call solver%release()
        call blocks(2, reshape([2.0_dp, 1.0_dp, 0.5_dp, 2.0_dp], [2, 2]), pattern, values, error)
        if (allocated(error)) return
        call factorise_solve(solver, pattern, values, [(1.0_dp, k = 1, 4)], x, declines, failure)
        call check(error, allocated(failure), 'unsymmetric under --linear-solver cholmod fails')
        if (allocated(error)) return
        call check(error, index(failure%message, 'not symmetric') > 0, &
                   'the message says why: '//failure%message)
    end subroutine test_forced

    !> factorise_values: the counts of the listing's solver lines (CHOLMOD factorisations,
    !> CHOLMOD declined), one factorisation each time, and the solve's x against the closed
    !> forms above.
    subroutine test_counts(error)
        type(error_t), allocatable, intent(out) :: error
        type(system_t) :: system
        type(stage_result_t) :: result
        real(dp), allocatable :: b(:), exact(:), x(:)
        integer :: k
        call bar(40, system%pattern, system%values, b, exact, error)
        if (allocated(error)) return
        call system%solver%configure(linear_solver_auto, .true.)
        call factorise_values(system, result, 'test', error)
        if (allocated(error)) return
        allocate (x(40))
        call system%solver%solve(system%pattern, system%values, b, x, error)
        if (allocated(error)) return
        call check(error, maxval(abs(x - exact)), 0.0_dp, 'bar by factorise_values', &
                   abs=1.0e-11_dp*maxval(abs(exact)))
        if (allocated(error)) return
        call system%solver%release()
        call blocks(2, reshape([1.0_dp, 2.0_dp, 2.0_dp, 1.0_dp], [2, 2]), system%pattern, &
                    system%values, error)
        if (allocated(error)) return
        call factorise_values(system, result, 'test', error)
        if (allocated(error)) return
        call check(error, result%factorisations, 2, 'factorisations')
        if (allocated(error)) return
        call check(error, result%stats%cholesky, 1, 'by CHOLMOD (the bar)')
        if (allocated(error)) return
        call check(error, result%stats%cholesky_declined, 1, 'declined (the indefinite one)')
        if (allocated(error)) return
        call check(error, result%stats%analyses, 3, &
                   'analyses: the bar, the blocks by CHOLMOD, then by UMFPACK')
        if (allocated(error)) return
        call system%solver%solve(system%pattern, system%values, [(1.0_dp, k = 1, 4)], &
                                 x(1:4), error)
        if (allocated(error)) return
        call check(error, maxval(abs(x(1:4) - 1.0_dp/3.0_dp)), 0.0_dp, &
                   'x = (1/3, 1/3) of each block by UMFPACK', abs=1.0e-14_dp)
    end subroutine test_counts

    !> The bar of test_bar_both by cholmod_t under each fill-reducing ordering (AMD, METIS,
    !> NESDIS): the closed form u = q (L x - x^2/2) / EA at every node, each time.
    subroutine test_orderings(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(cholmod_t) :: llt
        real(dp), allocatable :: values(:), b(:), exact(:), x(:)
        integer :: k
        integer, parameter :: n = 300, orderings(3) = [ordering_amd, ordering_metis, &
                                                       ordering_nesdis]
        character(len=6), parameter :: names(3) = [character(len=6) :: 'AMD', 'METIS', &
                                                   'NESDIS']
        logical :: positive
        call bar(n, pattern, values, b, exact, error)
        if (allocated(error)) return
        allocate (x(n))
        do k = 1, size(orderings)
            call llt%set_ordering(orderings(k))
            call llt%analyse(pattern, error)
            if (allocated(error)) return
            call llt%factorise(pattern, values, positive, error)
            if (allocated(error)) return
            call check(error, positive, 'the bar is positive definite')
            if (allocated(error)) return
            call llt%solve(b, x, error)
            if (allocated(error)) return
            call check(error, maxval(abs(x - exact)), 0.0_dp, &
                       'bar under uniform load against u = q (L x - x^2/2) / EA, ordering '// &
                       trim(names(k)), &
                       abs=1.0e-11_dp*maxval(abs(exact)))
            if (allocated(error)) return
            call llt%release()
        end do
    end subroutine test_orderings

    !> The ordering rule (docs/performance.md (y)): AMD for a constant tangent at any size,
    !> and for a varying one up to the largest measured (2e5 equations); NESDIS for a
    !> varying tangent beyond.
    subroutine test_ordering_rule(error)
        type(error_t), allocatable, intent(out) :: error
        call check(error, ordering_for(200000, .true.), ordering_amd, &
                   'constant tangent, 200,000 equations: AMD')
        if (allocated(error)) return
        call check(error, ordering_for(2000, .false.), ordering_amd, &
                   'varying tangent, 2,000 equations: AMD')
        if (allocated(error)) return
        call check(error, ordering_for(200000, .false.), ordering_amd, &
                   'varying tangent, 200,000 equations: AMD')
        if (allocated(error)) return
        call check(error, ordering_for(300000, .false.), ordering_nesdis, &
                   'varying tangent, 300,000 equations: NESDIS')
    end subroutine test_ordering_rule

    !> keep, then a second matrix (2 K) factorised with a copy of the kept analysis (no
    !> second analysis: factorise_values counts one), then restore: each solve against the
    !> bar's closed form (x / 2 for 2 K).
    subroutine test_kept_copy(error)
        type(error_t), allocatable, intent(out) :: error
        type(system_t) :: system
        type(stage_result_t) :: result
        real(dp), allocatable :: b(:), exact(:), x(:), k_values(:)
        logical :: kept
        call bar(60, system%pattern, k_values, b, exact, error)
        if (allocated(error)) return
        allocate (x(60))
        call system%solver%configure(linear_solver_auto, .true.)
        system%values = k_values
        call factorise_values(system, result, 'test', error)
        if (allocated(error)) return
        call system%solver%keep(kept)
        call check(error, kept, 'a CHOLMOD factorisation is kept')
        if (allocated(error)) return
        system%values = 2.0_dp*k_values
        call factorise_values(system, result, 'test', error)
        if (allocated(error)) return
        call check(error, result%stats%analyses, 1, 'analyses: the kept one copied, not redone')
        if (allocated(error)) return
        call check(error, system%solver%is_cholesky(), 'the copy factorised by CHOLMOD')
        if (allocated(error)) return
        call system%solver%solve(system%pattern, system%values, b, x, error)
        if (allocated(error)) return
        call check(error, maxval(abs(2.0_dp*x - exact)), 0.0_dp, &
                   'bar of stiffness 2 EA with the copied analysis against the closed form', &
                   abs=1.0e-11_dp*maxval(abs(exact)))
        if (allocated(error)) return
        call system%solver%restore()
        call system%solver%solve(system%pattern, k_values, b, x, error)
        if (allocated(error)) return
        call check(error, maxval(abs(x - exact)), 0.0_dp, &
                   'bar with the kept factorisation taken back against the closed form', &
                   abs=1.0e-11_dp*maxval(abs(exact)))
    end subroutine test_kept_copy

end module test_solver_cholmod
