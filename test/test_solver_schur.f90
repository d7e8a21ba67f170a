!> Tests of the saddle-point (contact) systems by CHOLMOD through K's Schur complement
!> (cfrd_schur, cfrd_linear_solver), against closed forms of two bars joined or held by
!> multiplier rows, as the contact rows join and hold bodies (docs/theory.md section 6):
!>
!> - bar A (length L, fixed at x = 0) and bar B (length L, held only by the multipliers),
!>   each of n linear elements, axial stiffness EA, uniform axial load q with consistent
!>   nodal loads; linear elements with consistent loads are exact at the nodes (Tong 1969;
!>   docs/theory.md section 7);
!> - multiplier 1 ties B's first node to A's last (u_B0 - u_An = 0): one bar of length 2 L
!>   fixed at 0, u(x) = q (2 L x - x^2 / 2) / EA, the tie's force q L;
!> - multiplier 2 holds B's last node (u_Bn = 0): A alone, u = q (L x - x^2 / 2) / EA, and
!>   B fixed at its far end, u(s) = q (L^2 - s^2) / (2 EA) (s from B's first node), the
!>   support's force q L;
!> - an open multiplier is the row p = 0 (a diagonal entry d, no coupling), as an open
!>   contact node's; with both open, B floats: the system is singular.
!> K alone is singular whenever B is held by multipliers only: the coupled equations' shift
!> is what lets CHOLMOD factorise it.
module test_solver_schur
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_sparse, only: sparse_pattern_t, build_pattern, assemble_element
    use cfrd_linear_solver, only: linear_solver_t, linear_solver_auto, linear_solver_umfpack, &
                                  linear_solver_cholmod
    use cfrd_schur, only: reduced_order_max
    implicit none
    private

    public :: collect_solver_schur

    real(dp), parameter :: bar_length = 10.0_dp, bar_ea = 2.0e6_dp, bar_q = 5.0_dp
    integer, parameter :: n = 8     !! elements per bar
    !> equations: A's nodes 1..n (node 0 fixed), B's nodes n+1 .. 2n+1, multipliers 2n+2, 2n+3
    integer, parameter :: nu = 2*n + 1, neq = nu + 2
    !> the reference's tolerance: round-off of the solves (the closed form is exact)
    real(dp), parameter :: tolerance = 1.0e-10_dp

contains

    subroutine collect_solver_schur(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('tied_bars_closed_form', test_tied), &
                new_unittest('new_rows_update_only_the_reduced_system', test_update), &
                new_unittest('floating_bar_is_singular', test_floating), &
                new_unittest('umfpack_forced_same_closed_form', test_umfpack), &
                new_unittest('unsymmetric_k_goes_to_umfpack', test_unsymmetric), &
                new_unittest('kept_k_taken_back', test_keep), &
                new_unittest('gap_and_load_right_hand_sides', test_right_hand_sides), &
                new_unittest('large_reduced_matrix_goes_to_umfpack', test_large), &
                new_unittest('partial_solve_then_complete', test_partial) &
                ]
    end subroutine collect_solver_schur

    !> The pattern (bars and both multiplier elements) and K's values with stiffness ea.
    subroutine two_bars(pattern, values, ea, error)
        type(sparse_pattern_t), intent(out) :: pattern
        real(dp), allocatable, intent(out) :: values(:)
        real(dp), intent(in) :: ea
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: dof_ptr(:), dofs(:)
        real(dp) :: h
        integer :: e
        allocate (dof_ptr(2*n + 3), dofs(4*n + 5))
        do e = 1, 2*n
            dof_ptr(e) = 2*e - 1
            if (e <= n) dofs(2*e - 1:2*e) = [e - 1, e]
            if (e > n) dofs(2*e - 1:2*e) = [e, e + 1]
        end do
        dof_ptr(2*n + 1) = 4*n + 1
        dofs(4*n + 1:4*n + 3) = [n, n + 1, neq - 1]     ! the tie: A_n, B_0, multiplier 1
        dof_ptr(2*n + 2) = 4*n + 4
        dofs(4*n + 4:4*n + 5) = [nu, neq]                ! the hold: B_n, multiplier 2
        dof_ptr(2*n + 3) = 4*n + 6
        call build_pattern(pattern, neq, dof_ptr, dofs, error)
        if (allocated(error)) return
        h = bar_length/n
        allocate (values(pattern%nnz), source=0.0_dp)
        do e = 1, 2*n
            call assemble_element(pattern, values, e, &
                                  ea/h*reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2]))
        end do
    end subroutine two_bars

    !> The multiplier rows: `tie` and `hold` active (the constraint) or open (p = 0, the
    !> diagonal d); the force columns are there either way, as a contact node's.
    subroutine rows(pattern, values, tie, hold)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(inout) :: values(:)
        logical, intent(in) :: tie, hold
        real(dp), parameter :: d = 1.0e6_dp
        real(dp) :: ke3(3, 3), ke2(2, 2)
        ke3 = 0.0_dp
        ke3(1:2, 3) = [-1.0_dp, 1.0_dp]*d
        if (tie) ke3(3, 1:2) = [-1.0_dp, 1.0_dp]*d
        if (.not. tie) ke3(3, 3) = d
        ke2 = 0.0_dp
        ke2(1, 2) = d
        if (hold) ke2(2, 1) = d
        if (.not. hold) ke2(2, 2) = d
        call assemble_element(pattern, values, 2*n + 1, ke3)
        call assemble_element(pattern, values, 2*n + 2, ke2)
    end subroutine rows

    !> Consistent nodal loads of both bars (the multiplier rows' right-hand side 0).
    function loads() result(b)
        real(dp), allocatable :: b(:)
        real(dp) :: h
        h = bar_length/n
        allocate (b(neq), source=0.0_dp)
        b(1:nu) = bar_q*h
        b(n) = 0.5_dp*bar_q*h
        b(n + 1) = 0.5_dp*bar_q*h
        b(nu) = 0.5_dp*bar_q*h
    end function loads

    !> The closed form with the tie (tied) or the hold (not tied); multipliers scaled by d.
    function exact(tied, ea) result(x)
        logical, intent(in) :: tied
        real(dp), intent(in) :: ea
        real(dp), allocatable :: x(:)
        real(dp), parameter :: d = 1.0e6_dp
        real(dp) :: h, s
        integer :: i
        h = bar_length/n
        allocate (x(neq), source=0.0_dp)
        do i = 1, n
            s = i*h
            x(i) = bar_q*(merge(2.0_dp, 1.0_dp, tied)*bar_length*s - 0.5_dp*s**2)/ea
        end do
        do i = 0, n
            s = i*h
            if (tied) then
                x(n + 1 + i) = bar_q*(2.0_dp*bar_length*(bar_length + s) - &
                                      0.5_dp*(bar_length + s)**2)/ea
            else
                x(n + 1 + i) = bar_q*(bar_length**2 - s**2)/(2.0_dp*ea)
            end if
        end do
        ! the force of the tie, or of the hold, on B: q L (times d, its column's coefficient)
        if (tied) x(neq - 1) = bar_q*bar_length/d
        if (.not. tied) x(neq) = bar_q*bar_length/d
    end function exact

    !> Largest |x - reference| over the largest |reference|, displacements and multipliers
    !> apart (their scales differ).
    subroutine check_against(error, x, reference, what)
        type(error_t), allocatable, intent(out) :: error
        real(dp), intent(in) :: x(:), reference(:)
        character(len=*), intent(in) :: what
        call check(error, maxval(abs(x(1:nu) - reference(1:nu)))/maxval(abs(reference(1:nu))) &
                   <= tolerance, what//': displacements against the closed form')
        if (allocated(error)) return
        call check(error, maxval(abs(x(nu + 1:) - reference(nu + 1:)))/ &
                   maxval(abs(reference(nu + 1:))) <= tolerance, &
                   what//': multipliers against the closed form')
    end subroutine check_against

    !> Factorise (analysis first) with the given solver choice.
    subroutine factorise(solver, pattern, values, error, reused)
        type(linear_solver_t), intent(inout) :: solver
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        logical, intent(out), optional :: reused
        logical :: declined
        call solver%choose(pattern, values, error)
        if (allocated(error)) return
        do
            if (.not. solver%is_analysed()) call solver%analyse(pattern, values, error)
            if (allocated(error)) return
            call solver%factorise(pattern, values, declined, error, reused)
            if (allocated(error) .or. .not. declined) return
        end do
    end subroutine factorise

    subroutine test_tied(error)
        type(error_t), allocatable, intent(out) :: error
        call solve_two_bars(error, linear_solver_auto, .true., .true., 'tied, CHOLMOD')
    end subroutine test_tied

    !> Two bars tied (else held), factorised under `choice`, the library checked
    !> (is_cholesky against `cholesky`), solved against the closed form.
    subroutine solve_two_bars(error, choice, tied, cholesky, what)
        type(error_t), allocatable, intent(out) :: error
        integer, intent(in) :: choice
        logical, intent(in) :: tied, cholesky
        character(len=*), intent(in) :: what
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: values(:), x(:)
        call two_bars(pattern, values, bar_ea, error)
        if (allocated(error)) return
        call rows(pattern, values, tied, .not. tied)
        call solver%configure(choice, .false., multipliers=2)
        call factorise(solver, pattern, values, error)
        if (allocated(error)) return
        call check(error, solver%is_cholesky() .eqv. cholesky, what//': the library')
        if (allocated(error)) return
        allocate (x(neq))
        call solver%solve(pattern, values, loads(), x, error)
        if (allocated(error)) return
        call check_against(error, x, exact(tied, bar_ea), what)
    end subroutine solve_two_bars

    !> A partial solve (what an active-set iteration reads): the multipliers and the
    !> coupled equations' displacements (A's last node, B's first and last) against the
    !> closed form, the other displacements zero; `complete` then gives all of them, as the
    !> whole solve does. Tied and held, CHOLMOD's path; under UMFPACK a partial solve is a
    !> whole one and `complete` leaves it as it is.
    subroutine test_partial(error)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: coupled(3) = [n, n + 1, nu]
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t), allocatable :: solver
        real(dp), allocatable :: values(:), x(:), reference(:)
        logical :: interior(nu)
        integer :: round
        character(len=24) :: what
        interior = .true.
        interior(coupled) = .false.
        do round = 1, 3
            what = merge('partial, tied   ', 'partial, held   ', round /= 2)
            if (round == 3) what = 'partial, UMFPACK'
            call two_bars(pattern, values, bar_ea, error)
            if (allocated(error)) return
            call rows(pattern, values, round /= 2, round == 2)
            if (allocated(solver)) then
                call solver%release()
                deallocate (solver)
            end if
            allocate (solver)
            call solver%configure(merge(linear_solver_umfpack, linear_solver_auto, round == 3), &
                                  .false., multipliers=2)
            call factorise(solver, pattern, values, error)
            if (allocated(error)) return
            reference = exact(round /= 2, bar_ea)
            allocate (x(neq))
            call solver%solve(pattern, values, loads(), x, error, partial=.true.)
            if (allocated(error)) return
            call check(error, maxval(abs(x(coupled) - reference(coupled)))/ &
                       maxval(abs(reference(1:nu))) <= tolerance .and. &
                       maxval(abs(x(nu + 1:) - reference(nu + 1:)))/ &
                       maxval(abs(reference(nu + 1:))) <= tolerance, &
                       trim(what)//': the coupled displacements and the multipliers')
            if (allocated(error)) return
            if (round < 3) then
                call check(error, all(x(1:nu) == 0.0_dp .or. .not. interior), &
                           trim(what)//': the other displacements are left for complete')
            else
                call check_against(error, x, reference, trim(what)//' (a whole solve)')
            end if
            if (allocated(error)) return
            call solver%complete(x, error)
            if (allocated(error)) return
            call check_against(error, x, reference, trim(what)//', completed')
            if (allocated(error)) return
            deallocate (x)
        end do
        call solver%release()
    end subroutine test_partial

    !> Tie, then hold, then tie again: the same K, new rows, each an update of R alone.
    subroutine test_update(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: k_values(:), values(:), x(:)
        logical :: done
        integer :: round
        call two_bars(pattern, k_values, bar_ea, error)
        if (allocated(error)) return
        values = k_values
        call rows(pattern, values, .true., .false.)
        call solver%configure(linear_solver_auto, .false., multipliers=2)
        call factorise(solver, pattern, values, error)
        if (allocated(error)) return
        allocate (x(neq))
        do round = 1, 2
            values = k_values
            call rows(pattern, values, round == 2, round == 1)
            call solver%update_rows(pattern, values, done, error)
            if (allocated(error)) return
            call check(error, done .and. solver%is_cholesky(), 'new rows: an update')
            if (allocated(error)) return
            call solver%solve(pattern, values, loads(), x, error)
            if (allocated(error)) return
            call check_against(error, x, exact(round == 2, bar_ea), 'updated')
            if (allocated(error)) return
        end do
        ! another K: not an update
        values = 2.0_dp*k_values
        call rows(pattern, values, .true., .false.)
        call solver%update_rows(pattern, values, done, error)
        if (allocated(error)) return
        call check(error, .not. done, 'another K is not updated')
    end subroutine test_update

    !> Both rows open: B floats, the system is singular (an error that says so, as
    !> UMFPACK's), whether factorised or updated.
    subroutine test_floating(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        type(error_t), allocatable :: singular
        real(dp), allocatable :: k_values(:), values(:)
        logical :: done
        call two_bars(pattern, k_values, bar_ea, error)
        if (allocated(error)) return
        values = k_values
        call rows(pattern, values, .false., .false.)
        call solver%configure(linear_solver_auto, .false., multipliers=2)
        call factorise(solver, pattern, values, singular)
        call check(error, allocated(singular), 'a floating bar is an error')
        if (allocated(error)) return
        call check(error, index(singular%message, 'singular') > 0, &
                   'the message says singular: '//singular%message)
        if (allocated(error)) return
        values = k_values
        call rows(pattern, values, .true., .false.)
        call factorise(solver, pattern, values, error)
        if (allocated(error)) return
        values = k_values
        call rows(pattern, values, .false., .false.)
        call solver%update_rows(pattern, values, done, error)
        if (allocated(error)) return
        call check(error, .not. done, 'a singular update is declined (factorise reports it)')
    end subroutine test_floating

    !> --linear-solver umfpack: the same closed forms by UMFPACK.
    subroutine test_umfpack(error)
        type(error_t), allocatable, intent(out) :: error
        call solve_two_bars(error, linear_solver_umfpack, .false., .false., 'held, UMFPACK')
    end subroutine test_umfpack

    !> K not symmetric (a Newton tangent's case): UMFPACK, under auto and cholmod alike. A
    !> coupling of A's first two nodes one way only leaves the tied solution's A-part
    !> changed, so the check is the residual of the solve, not the closed form.
    subroutine test_unsymmetric(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: values(:), x(:), b(:), r(:)
        integer :: choice, j, p
        do choice = linear_solver_auto, linear_solver_cholmod
            call two_bars(pattern, values, bar_ea, error)
            if (allocated(error)) return
            call rows(pattern, values, .true., .false.)
            ! entry (1, 2) of K one tenth stiffer than (2, 1)
            do p = pattern%colptr(2) + 1, pattern%colptr(3)
                if (pattern%rowind(p) == 0) values(p) = 1.1_dp*values(p)
            end do
            call solver%configure(choice, .false., multipliers=2)
            call factorise(solver, pattern, values, error)
            if (allocated(error)) return
            call check(error, .not. solver%is_cholesky(), 'an unsymmetric K goes to UMFPACK')
            if (allocated(error)) return
            b = loads()
            allocate (x(neq), r(neq))
            call solver%solve(pattern, values, b, x, error)
            if (allocated(error)) return
            r = b
            do j = 1, neq
                do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                    r(pattern%rowind(p) + 1) = r(pattern%rowind(p) + 1) - values(p)*x(j)
                end do
            end do
            call check(error, maxval(abs(r))/maxval(abs(b)) <= tolerance, &
                       'the unsymmetric system solved (residual)')
            if (allocated(error)) return
            deallocate (x, r)
            call solver%release()
        end do
    end subroutine test_unsymmetric

    !> keep sets K's factorisation aside; a factorisation of another K goes on; the first K
    !> given again is taken back (reused, not factorised), and solves as before.
    subroutine test_keep(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: first(:), second(:), x(:)
        logical :: kept, reused
        call two_bars(pattern, first, bar_ea, error)
        if (allocated(error)) return
        call rows(pattern, first, .true., .false.)
        call two_bars(pattern, second, 3.0_dp*bar_ea, error)
        if (allocated(error)) return
        call rows(pattern, second, .false., .true.)
        call solver%configure(linear_solver_auto, .false., multipliers=2)
        call factorise(solver, pattern, first, error)
        if (allocated(error)) return
        call solver%keep(kept)
        call factorise(solver, pattern, second, error, reused)
        if (allocated(error)) return
        call check(error, .not. reused, 'another K is factorised')
        if (allocated(error)) return
        allocate (x(neq))
        call solver%solve(pattern, second, loads(), x, error)
        if (allocated(error)) return
        call check_against(error, x, exact(.false., 3.0_dp*bar_ea), 'second K')
        if (allocated(error)) return
        call factorise(solver, pattern, first, error, reused)
        if (allocated(error)) return
        call check(error, reused, 'the kept K is taken back')
        if (allocated(error)) return
        call solver%solve(pattern, first, loads(), x, error)
        if (allocated(error)) return
        call check_against(error, x, exact(.true., bar_ea), 'taken back')
    end subroutine test_keep

    !> The tie with a gap g (its row's right-hand side d g: u_B0 - u_An = g): B moves by g,
    !> A and the tie's force as without it; then twice the load: twice the tied solution.
    !> The same load with another multiplier right-hand side is the case the kept forward
    !> half serves, another load the case it must not.
    subroutine test_right_hand_sides(error)
        type(error_t), allocatable, intent(out) :: error
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: values(:), x(:), b(:), reference(:)
        real(dp), parameter :: d = 1.0e6_dp, gap = 1.0e-3_dp
        call two_bars(pattern, values, bar_ea, error)
        if (allocated(error)) return
        call rows(pattern, values, .true., .false.)
        call solver%configure(linear_solver_auto, .false., multipliers=2)
        call factorise(solver, pattern, values, error)
        if (allocated(error)) return
        allocate (x(neq))
        b = loads()
        call solver%solve(pattern, values, b, x, error)
        if (allocated(error)) return
        call check_against(error, x, exact(.true., bar_ea), 'no gap')
        if (allocated(error)) return
        b(neq - 1) = d*gap
        call solver%solve(pattern, values, b, x, error)
        if (allocated(error)) return
        reference = exact(.true., bar_ea)
        reference(n + 1:nu) = reference(n + 1:nu) + gap
        call check_against(error, x, reference, 'gap')
        if (allocated(error)) return
        b = 2.0_dp*loads()
        call solver%solve(pattern, values, b, x, error)
        if (allocated(error)) return
        call check_against(error, x, 2.0_dp*exact(.true., bar_ea), 'twice the load')
    end subroutine test_right_hand_sides

    !> Springs of stiffness k, each tied by its own multiplier to a gap g (d u_i = d g) under
    !> a force f: u_i = g and lambda_i = (f - k g) / d (closed form). With the reduced order
    !> (springs + multipliers) at reduced_order_max the system goes to CHOLMOD, one spring
    !> more to UMFPACK; both solve it.
    subroutine test_large(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: k = 3.0e4_dp, d = 1.0e4_dp, f = 50.0_dp, g = 2.0e-3_dp
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver
        real(dp), allocatable :: values(:), b(:), x(:)
        integer, allocatable :: dof_ptr(:), dofs(:)
        integer :: springs, e, round
        do round = 1, 2
            springs = reduced_order_max/2 + (round - 1)
            dof_ptr = [(2*e - 1, e=1, springs + 1)]
            dofs = [([e, springs + e], e=1, springs)]
            call build_pattern(pattern, 2*springs, dof_ptr, dofs, error)
            if (allocated(error)) return
            allocate (values(pattern%nnz), source=0.0_dp)
            do e = 1, springs
                call assemble_element(pattern, values, e, reshape([k, d, d, 0.0_dp], [2, 2]))
            end do
            b = [(f, e=1, springs), (d*g, e=1, springs)]
            allocate (x(2*springs))
            call solver%configure(linear_solver_auto, .false., multipliers=springs)
            call factorise(solver, pattern, values, error)
            if (allocated(error)) return
            call check(error, solver%is_cholesky() .eqv. (round == 1), &
                       'CHOLMOD up to reduced_order_max, UMFPACK beyond')
            if (allocated(error)) return
            call solver%solve(pattern, values, b, x, error)
            if (allocated(error)) return
            call check(error, maxval(abs(x(1:springs) - g)) <= tolerance*g .and. &
                       maxval(abs(x(springs + 1:) - (f - k*g)/d)) <= &
                       tolerance*abs((f - k*g)/d), 'springs against the closed form')
            if (allocated(error)) return
            call solver%release()
            deallocate (values, x)
        end do
    end subroutine test_large

end module test_solver_schur
