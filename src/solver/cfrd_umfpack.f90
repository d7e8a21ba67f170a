!> UMFPACK (SuiteSparse) for the stiffness equations, bound in two layers: private bind(C)
!> interfaces to the `umfpack_di_*` routines (int indices, double values), and a public
!> `umfpack_t` that keeps the symbolic factorisation for as long as the pattern holds, checks
!> every status, turns singularity into an error_t and frees its handles on every path.
!> A matrix that differs from the factorised one in a few rows (the contact rows of an
!> active-set iteration) can be solved through that factorisation by a low-rank update
!> (update_rows) instead of a new numeric factorisation.
module cfrd_umfpack
    use, intrinsic :: iso_c_binding, only: c_int, c_double, c_ptr, c_null_ptr, c_associated
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, numerical_error
    use cfrd_sparse, only: sparse_pattern_t
    use cfrd_lapack, only: dgetrf, dgetrs, dgecon
    implicit none
    private

    public :: umfpack_t, rcond_min, umfpack_status_text, max_update_rank, singular_text

    !> Below this reciprocal condition estimate the solution is refused: about 500 times the
    !> double-precision machine epsilon (2.2e-16). The error of a solve grows like eps/rcond, so
    !> below it fewer than three digits could be trusted; the estimate is of the row-scaled
    !> matrix, so it sees stiffness contrasts and rigid-body modes, not differences of units.
    real(dp), parameter :: rcond_min = 1.0e-13_dp

    !> Most rows an update (update_rows) may change against the factorised matrix. Each row
    !> costs one solve with the factors when it first differs, and its column serves the
    !> later updates of the same factorisation; a numeric factorisation of the
    !> Tianshengqiao-I contact systems costs about 15 (20818 equations) to 40 (1366) solves.
    !> 8, 24, 32 and 64 were measured on the x4 contact deck (docs/performance.md, "The rank
    !> of the low-rank updates"): 8 factorises too often, 24 to 64 are equal within the noise.
    integer, parameter :: max_update_rank = 32
    !> Below this reciprocal condition estimate of the update's capacitance matrix the
    !> update is declined and the matrix factorised: its conditioning is then UMFPACK's to
    !> judge (rcond_min), and the solves do not lose digits to the update.
    real(dp), parameter :: update_rcond_min = 1.0e-10_dp
    !> Iterative refinement steps of an updated solve. One: measured on the x4 contact
    !> deck, the first step leaves a backward error of at most 3.6e-16 in all 115 updated
    !> solves (before it up to 1.6e-6), a second one gained nothing that counts
    !> (docs/performance.md (ab)); UMFPACK's own default is 2 (UMFPACK_IRSTEP).
    integer, parameter :: update_refinements = 1
    !> The largest backward error an updated solve may leave (UMFPACK's own solves of these
    !> systems leave about 2e-16); above it the matrix is factorised instead.
    real(dp), parameter :: update_omega_max = 1.0e-13_dp

    ! Sizes and indices of umfpack.h (0-based in C, hence the +1 in Fortran).
    integer, parameter :: umfpack_control = 20, umfpack_info = 90
    integer, parameter :: i_prl = 0, i_strategy = 5, i_ordering = 10, i_scale = 16
    integer, parameter :: i_rcond = 67, i_irstep = 7
    integer, parameter :: i_nrow = 1, i_lnz = 43, i_unz = 44
    integer(c_int), parameter :: ordering_amd = 1, ordering_metis = 3
    integer(c_int), parameter :: umfpack_a = 0
    integer(c_int), parameter :: strategy_symmetric = 3
    integer(c_int), parameter :: scale_none = 0, scale_sum = 1
    integer(c_int), parameter :: umfpack_ok = 0, warning_singular = 1

    !> A factorisation of one sparse matrix pattern.
    type :: umfpack_t
        private
        type(c_ptr) :: symbolic = c_null_ptr
        type(c_ptr) :: numeric = c_null_ptr
        real(c_double) :: control(umfpack_control) = 0.0_dp
        real(c_double) :: info(umfpack_info) = 0.0_dp
        logical :: configured = .false.
        logical :: row_scaling = .true.
        ! The row update (update_rows): the factorised matrix A0 has the values `base`; the
        ! matrix solved is A1 = A0 + E D, E the unit columns of rows(1:rank), D the rows of
        ! A1 - A0 there (triplets: slot in rows, column, value); w = A0^-1 E and the
        ! capacitance matrix S = I + D w (LU-factorised) give A1^-1 = (I - w S^-1 D) A0^-1.
        logical :: updated = .false.           !! solves are of A1, not of A0
        real(dp), allocatable :: base(:)       !! (nnz) values of A0
        integer :: rank = 0                    !! rows whose w columns are computed
        integer :: rows(max_update_rank) = 0
        real(dp), allocatable :: w(:, :)       !! (n, max_update_rank)
        real(dp) :: capacitance(max_update_rank, max_update_rank) = 0.0_dp
        !> 1 / the largest magnitude of each row of S: the rows of D are of K's size, while a
        !> unit row of S is not, so S is equilibrated before its LU factorisation
        real(dp) :: row_factor(max_update_rank) = 1.0_dp
        integer :: pivots(max_update_rank) = 0
        integer, allocatable :: d_slot(:), d_col(:)
        real(dp), allocatable :: d_value(:)
        !> The load and solution of the last solve of A0 itself: a load that differs from it
        !> only in rows(1:rank) has A0^-1 b = x_base + w (b - b_base)(rows), no solve needed
        real(dp), allocatable :: b_base(:), x_base(:)
        !> A numeric factorisation set aside (set_aside) with its matrix and UMFPACK's info:
        !> taken back, not redone, when factorise is given the same matrix again (the retry
        !> of a rejected increment from the same state; docs/performance.md (ac))
        type(c_ptr) :: spare = c_null_ptr
        real(dp), allocatable :: spare_base(:)
        real(c_double) :: spare_info(umfpack_info) = 0.0_dp
    contains
        procedure :: set_row_scaling
        procedure :: set_refinement
        procedure :: set_metis
        procedure :: analyse
        procedure :: factorise
        procedure :: set_aside
        procedure :: update_rows
        procedure :: solve
        procedure :: rcond
        procedure :: factor_nonzeros
        procedure :: is_updated
        procedure :: release
        procedure, private :: solve_factors, solve_updated, forget_update, free_spare, &
                              spare_matches, drop_solve_state
        final :: finalise
    end type umfpack_t

    interface
        subroutine umfpack_di_defaults(control) bind(C, name='umfpack_di_defaults')
            import :: c_double
            real(c_double), intent(out) :: control(*)
        end subroutine umfpack_di_defaults

        integer(c_int) function umfpack_di_symbolic(n_row, n_col, ap, ai, ax, symbolic, &
                                                    control, info) &
            bind(C, name='umfpack_di_symbolic')
            import :: c_int, c_double, c_ptr
            integer(c_int), value :: n_row, n_col
            integer(c_int), intent(in) :: ap(*), ai(*)
            real(c_double), intent(in) :: ax(*)
            type(c_ptr), intent(out) :: symbolic
            real(c_double), intent(in) :: control(*)
            real(c_double), intent(out) :: info(*)
        end function umfpack_di_symbolic

        integer(c_int) function umfpack_di_numeric(ap, ai, ax, symbolic, numeric, control, &
                                                   info) bind(C, name='umfpack_di_numeric')
            import :: c_int, c_double, c_ptr
            integer(c_int), intent(in) :: ap(*), ai(*)
            real(c_double), intent(in) :: ax(*)
            type(c_ptr), value :: symbolic
            type(c_ptr), intent(out) :: numeric
            real(c_double), intent(in) :: control(*)
            real(c_double), intent(out) :: info(*)
        end function umfpack_di_numeric

        integer(c_int) function umfpack_di_solve(sys, ap, ai, ax, x, b, numeric, control, &
                                                 info) bind(C, name='umfpack_di_solve')
            import :: c_int, c_double, c_ptr
            integer(c_int), value :: sys
            integer(c_int), intent(in) :: ap(*), ai(*)
            real(c_double), intent(in) :: ax(*)
            real(c_double), intent(out) :: x(*)
            real(c_double), intent(in) :: b(*)
            type(c_ptr), value :: numeric
            real(c_double), intent(in) :: control(*)
            real(c_double), intent(out) :: info(*)
        end function umfpack_di_solve

        subroutine umfpack_di_free_symbolic(symbolic) bind(C, name='umfpack_di_free_symbolic')
            import :: c_ptr
            type(c_ptr), intent(inout) :: symbolic
        end subroutine umfpack_di_free_symbolic

        subroutine umfpack_di_free_numeric(numeric) bind(C, name='umfpack_di_free_numeric')
            import :: c_ptr
            type(c_ptr), intent(inout) :: numeric
        end subroutine umfpack_di_free_numeric
    end interface

contains

    !> UMFPACK's defaults, silent, with the symmetric strategy: a stiffness matrix is
    !> symmetric with a non-zero diagonal, so an AMD ordering of A + A^T with diagonal pivots
    !> gives far less fill than the unsymmetric strategy's column ordering. AMD alone, not
    !> the default that also tries METIS: on 2D meshes of 10^5 quads METIS costs more time in
    !> the symbolic phase than it saves in the numeric one (docs/performance.md).
    subroutine configure(self)
        class(umfpack_t), intent(inout) :: self
        if (self%configured) return
        call umfpack_di_defaults(self%control)
        self%control(i_prl + 1) = 0.0_dp
        self%control(i_strategy + 1) = real(strategy_symmetric, c_double)
        self%control(i_ordering + 1) = real(ordering_amd, c_double)
        self%control(i_scale + 1) = real(merge(scale_sum, scale_none, self%row_scaling), &
                                         c_double)
        self%configured = .true.
    end subroutine configure

    !> UMFPACK's row scaling (each row divided by the sum of its magnitudes before pivoting;
    !> on by default). A saddle-point system whose constraint rows are already scaled to the
    !> size of K's entries (contact, docs/theory.md section 14) is factorised faster without
    !> it: the scaling magnifies the short constraint rows, so that far more pivots leave the
    !> diagonal (docs/performance.md, "Row scaling of the contact systems"). Takes effect at
    !> the next factorisation.
    subroutine set_row_scaling(self, on)
        class(umfpack_t), intent(inout) :: self
        logical, intent(in) :: on
        self%row_scaling = on
        if (self%configured) self%control(i_scale + 1) = &
            real(merge(scale_sum, scale_none, on), c_double)
    end subroutine set_row_scaling

    !> UMFPACK's iterative refinement of its solves (UMFPACK_IRSTEP: its default, 2 steps,
    !> when on; none when off). Off for Newton's corrections, which the next iteration
    !> corrects in turn (docs/theory.md section 9, "Newton's solves and
    !> factorisations"), and for the contact systems, whose updated solves refine on
    !> their own (refined_solve; docs/theory.md section 6).
    subroutine set_refinement(self, on)
        class(umfpack_t), intent(inout) :: self
        logical, intent(in) :: on
        real(c_double) :: defaults(umfpack_control)
        call configure(self)
        call umfpack_di_defaults(defaults)
        self%control(i_irstep + 1) = merge(defaults(i_irstep + 1), 0.0_dp, on)
    end subroutine set_refinement

    !> UMFPACK's METIS ordering of A + A^T in place of AMD (UMFPACK_ORDERING_METIS) for
    !> Newton's consistent tangents: at x4 16 % less fill and 5 % less CPU time of the run,
    !> for a costlier analysis once per pattern (docs/performance.md (z)); and for the
    !> larger contact systems (docs/performance.md (ab)). Takes effect at the next
    !> symbolic analysis.
    subroutine set_metis(self, on)
        class(umfpack_t), intent(inout) :: self
        logical, intent(in) :: on
        call configure(self)
        self%control(i_ordering + 1) = real(merge(ordering_metis, ordering_amd, on), c_double)
    end subroutine set_metis

    !> Symbolic factorisation (ordering and analysis) of the pattern; replaces an earlier one.
    subroutine analyse(self, pattern, values, error)
        class(umfpack_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        integer(c_int) :: status
        call configure(self)
        call self%release()
        call check_sizes(pattern, values, error)
        if (allocated(error)) return
        status = umfpack_di_symbolic(int(pattern%n, c_int), int(pattern%n, c_int), &
                                     pattern%colptr, pattern%rowind, values, self%symbolic, &
                                     self%control, self%info)
        if (status /= umfpack_ok) then
            call self%release()
            call fatal_error(error, 'symbolic factorisation failed: '// &
                             umfpack_status_text(int(status)), numerical_error)
        end if
    end subroutine analyse

    !> Numeric factorisation with the kept symbolic one (made first if there is none).
    !> A singular or nearly singular matrix is an error; no factorisation is kept then.
    !> `reused`: the matrix is, bit for bit, the one of the factorisation set aside
    !> (set_aside), which is taken back instead (the same factors as a new one would be).
    subroutine factorise(self, pattern, values, error, reused)
        class(umfpack_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        logical, intent(out), optional :: reused
        integer(c_int) :: status
        if (present(reused)) reused = .false.
        call check_sizes(pattern, values, error)
        if (allocated(error)) return
        if (.not. c_associated(self%symbolic)) then
            call self%analyse(pattern, values, error)
            if (allocated(error)) return
        end if
        if (c_associated(self%numeric)) call umfpack_di_free_numeric(self%numeric)
        call self%drop_solve_state()
        if (self%spare_matches(pattern, values)) then
            self%numeric = self%spare
            self%spare = c_null_ptr
            call move_alloc(self%spare_base, self%base)
            self%info = self%spare_info
            if (present(reused)) reused = .true.
            return
        end if
        status = umfpack_di_numeric(pattern%colptr, pattern%rowind, values, self%symbolic, &
                                    self%numeric, self%control, self%info)
        if (status == warning_singular .or. &
            (status == umfpack_ok .and. .not. (self%rcond() >= rcond_min))) then
            call fatal_error(error, singular_text(umfpack_status_text(int(status)), &
                                                  self%rcond()), numerical_error)
        else if (status /= umfpack_ok) then
            call fatal_error(error, 'numeric factorisation failed: '// &
                             umfpack_status_text(int(status)), numerical_error)
        end if
        if (allocated(error)) then
            if (c_associated(self%numeric)) call umfpack_di_free_numeric(self%numeric)
            self%numeric = c_null_ptr
        else
            self%base = values(1:pattern%nnz)
        end if
    end subroutine factorise

    !> Whether the factorisation set aside is that of `values`, bit for bit (ALL stops at
    !> the first difference).
    logical function spare_matches(self, pattern, values) result(matches)
        class(umfpack_t), intent(in) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        matches = c_associated(self%spare)
        if (matches) matches = size(self%spare_base) == pattern%nnz
        if (matches) matches = all(self%spare_base == values(1:pattern%nnz))
    end function spare_matches

    !> What the solves kept of the factorisation in use (its low-rank update and the base
    !> solve of A0), dropped when that factorisation is replaced or set aside.
    subroutine drop_solve_state(self)
        class(umfpack_t), intent(inout) :: self
        call self%forget_update()
        if (allocated(self%b_base)) deallocate (self%b_base, self%x_base)
    end subroutine drop_solve_state

    !> Set the numeric factorisation aside (replacing one set aside before): factorise takes
    !> it back when it is given its matrix again. The solves have no factorisation until
    !> the next factorise.
    subroutine set_aside(self)
        class(umfpack_t), intent(inout) :: self
        call self%free_spare()
        if (.not. (c_associated(self%numeric) .and. allocated(self%base))) return
        self%spare = self%numeric
        self%numeric = c_null_ptr
        call move_alloc(self%base, self%spare_base)
        self%spare_info = self%info
        call self%drop_solve_state()
    end subroutine set_aside

    !> Free the factorisation set aside, if any.
    subroutine free_spare(self)
        class(umfpack_t), intent(inout) :: self
        if (c_associated(self%spare)) call umfpack_di_free_numeric(self%spare)
        self%spare = c_null_ptr
        if (allocated(self%spare_base)) deallocate (self%spare_base)
    end subroutine free_spare

    !> Make the solves those of `values`, a matrix of the factorised one's pattern that differs
    !> from it in at most max_update_rank rows, without a new numeric factorisation (the
    !> Sherman-Morrison-Woodbury formula; one solve with the factors per row that differs for
    !> the first time since the factorisation). `done` is false, and the solves stay those of
    !> the factorised matrix, when more rows differ, when there is no factorisation, or when
    !> the update is ill-conditioned: the caller then factorises `values`. `refused` (also
    !> not done) when a column of w or the capacitance matrix is not finite: the update is
    !> declined before LAPACK sees it. When no row differs and none did before, `values` is
    !> the factorised matrix: done, and the solves are the factorisation's own (nothing to
    !> update: an empty capacitance matrix would reach LAPACK's dgecon with the norm of an
    !> empty matrix, -huge, and a factorisation of the same values would give the same
    !> factors; docs/robustness.md, "The empty row update").
    subroutine update_rows(self, pattern, values, done, error, refused)
        class(umfpack_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        logical, intent(out) :: done
        type(error_t), allocatable, intent(out) :: error
        logical, intent(out), optional :: refused
        integer, allocatable :: slot(:)
        real(dp), allocatable :: unit_column(:)
        real(dp) :: anorm, rcond_s, work(4*max_update_rank)
        integer :: iwork(max_update_rank), rank, j, p, k, nd, status
        done = .false.
        if (present(refused)) refused = .false.
        self%updated = .false.
        if (.not. c_associated(self%numeric) .or. .not. allocated(self%base)) return
        call check_sizes(pattern, values, error)
        if (allocated(error)) return
        if (size(self%base) /= pattern%nnz) return
        ! The rows that differ: those of earlier updates (their w columns are kept), then
        ! the new ones.
        allocate (slot(pattern%n), source=0)
        do k = 1, self%rank
            slot(self%rows(k)) = k
        end do
        rank = self%rank
        nd = 0
        do p = 1, pattern%nnz
            if (values(p) == self%base(p)) cycle
            nd = nd + 1
            if (slot(pattern%rowind(p) + 1) > 0) cycle
            rank = rank + 1
            if (rank > max_update_rank) return
            slot(pattern%rowind(p) + 1) = rank
            self%rows(rank) = pattern%rowind(p) + 1
        end do
        if (rank == 0) then             ! the factorised matrix itself
            done = .true.
            return
        end if
        if (.not. allocated(self%w)) then
            allocate (self%w(pattern%n, max_update_rank))
        else if (size(self%w, 1) /= pattern%n) then
            deallocate (self%w)
            allocate (self%w(pattern%n, max_update_rank))
        end if
        allocate (unit_column(pattern%n), source=0.0_dp)
        do k = self%rank + 1, rank
            unit_column(self%rows(k)) = 1.0_dp
            call self%solve_factors(pattern, unit_column, self%w(:, k), error)
            unit_column(self%rows(k)) = 0.0_dp
            if (allocated(error)) then
                self%rank = 0
                return
            end if
            if (.not. all(ieee_is_finite(self%w(:, k)))) then
                if (present(refused)) refused = .true.
                return
            end if
            self%rank = k
        end do
        ! D as triplets, and S = I + D w.
        self%d_slot = [integer :: (0, k = 1, nd)]
        self%d_col = self%d_slot
        self%d_value = [real(dp) :: (0.0_dp, k = 1, nd)]
        nd = 0
        do j = 1, pattern%n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                if (values(p) == self%base(p)) cycle
                nd = nd + 1
                self%d_slot(nd) = slot(pattern%rowind(p) + 1)
                self%d_col(nd) = j
                self%d_value(nd) = values(p) - self%base(p)
            end do
        end do
        associate (s => self%capacitance(1:rank, 1:rank))
            s = 0.0_dp
            do k = 1, rank
                s(k, k) = 1.0_dp
            end do
            do p = 1, nd
                s(self%d_slot(p), :) = s(self%d_slot(p), :) + &
                                       self%d_value(p)*self%w(self%d_col(p), 1:rank)
            end do
            ! before any comparison with its entries (a NaN would trap in the debug build)
            if (.not. all(ieee_is_finite(s))) then
                if (present(refused)) refused = .true.
                return
            end if
            do k = 1, rank
                self%row_factor(k) = 1.0_dp/max(maxval(abs(s(k, :))), tiny(1.0_dp))
                s(k, :) = self%row_factor(k)*s(k, :)
            end do
            anorm = maxval(sum(abs(s), dim=1))
            if (.not. ieee_is_finite(anorm)) then
                if (present(refused)) refused = .true.
                return
            end if
        end associate
        call dgetrf(rank, rank, self%capacitance, max_update_rank, self%pivots, status)
        if (status /= 0) return
        call dgecon('1', rank, self%capacitance, max_update_rank, anorm, rcond_s, work, &
                    iwork, status)
        if (status /= 0 .or. .not. (rcond_s >= update_rcond_min)) return
        self%updated = .true.
        done = .true.
    end subroutine update_rows

    !> x = A0^-1 b with the factors alone (no refinement: the updated solve refines against
    !> the updated matrix); its own info array, so that the factorisation's figures stay.
    subroutine solve_factors(self, pattern, b, x, error)
        class(umfpack_t), intent(in) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: b(:)
        real(dp), intent(out) :: x(:)
        type(error_t), allocatable, intent(out) :: error
        real(c_double) :: control(umfpack_control), info(umfpack_info)
        integer(c_int) :: status
        control = self%control
        control(i_irstep + 1) = 0.0_dp
        status = umfpack_di_solve(umfpack_a, pattern%colptr, pattern%rowind, self%base, x, b, &
                                  self%numeric, control, info)
        if (status /= umfpack_ok) call fatal_error(error, 'solve failed: '// &
                                                   umfpack_status_text(int(status)), &
                                                   numerical_error)
    end subroutine solve_factors

    !> x = A1^-1 b = (I - w S^-1 D) A0^-1 b. With `load`, b may be the last load of A0
    !> changed in the updated rows (an active-set iteration changes the right-hand sides of
    !> the contact rows it changes, and only those): A0^-1 b is then had without a solve.
    subroutine solve_updated(self, pattern, b, x, error, load)
        class(umfpack_t), intent(in) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: b(:)
        real(dp), intent(out) :: x(:)
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in), optional :: load
        real(dp) :: t(max_update_rank, 1)
        real(dp), allocatable :: change(:)
        integer :: p, status
        logical :: known
        known = .false.
        if (present(load) .and. allocated(self%b_base)) then
            change = b(1:pattern%n) - self%b_base
            t(1:self%rank, 1) = change(self%rows(1:self%rank))
            change(self%rows(1:self%rank)) = 0.0_dp
            known = all(change == 0.0_dp)
        end if
        if (known) then
            x(1:pattern%n) = self%x_base + matmul(self%w(:, 1:self%rank), t(1:self%rank, 1))
        else
            call self%solve_factors(pattern, b, x, error)
            if (allocated(error)) return
        end if
        t = 0.0_dp
        do p = 1, size(self%d_slot)
            t(self%d_slot(p), 1) = t(self%d_slot(p), 1) + self%d_value(p)*x(self%d_col(p))
        end do
        t(1:self%rank, 1) = self%row_factor(1:self%rank)*t(1:self%rank, 1)
        call dgetrs('N', self%rank, 1, self%capacitance, max_update_rank, self%pivots, t, &
                    max_update_rank, status)
        x(1:pattern%n) = x(1:pattern%n) - matmul(self%w(:, 1:self%rank), t(1:self%rank, 1))
    end subroutine solve_updated

    !> The solves are those of an updated matrix (update_rows), not of the factorised one.
    logical function is_updated(self)
        class(umfpack_t), intent(in) :: self
        is_updated = self%updated
    end function is_updated

    !> Forget an update: the solves are those of the factorised matrix again.
    subroutine forget_update(self)
        class(umfpack_t), intent(inout) :: self
        self%updated = .false.
        self%rank = 0
    end subroutine forget_update

    !> C reads and writes whole arrays without bounds checks, so short ones are caught here.
    pure subroutine check_sizes(pattern, values, error, size_b, size_x)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        integer, intent(in), optional :: size_b, size_x
        logical :: short
        short = .not. allocated(pattern%colptr) .or. .not. allocated(pattern%rowind)
        if (.not. short) short = size(pattern%colptr) < pattern%n + 1 .or. &
                                 size(pattern%rowind) < pattern%nnz .or. &
                                 size(values) < pattern%nnz
        if (present(size_b)) short = short .or. size_b < pattern%n
        if (present(size_x)) short = short .or. size_x < pattern%n
        if (short) call fatal_error(error, 'internal: sparse matrix or vector shorter than '// &
                                    'its pattern says', numerical_error)
    end subroutine check_sizes

    !> Solve A x = b with the current numeric factorisation.
    subroutine solve(self, pattern, values, b, x, error)
        class(umfpack_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:), b(:)
        real(dp), intent(out) :: x(:)
        type(error_t), allocatable, intent(out) :: error
        integer(c_int) :: status
        if (.not. c_associated(self%numeric)) then
            call fatal_error(error, 'internal: solve called without a factorisation', &
                             numerical_error)
            return
        end if
        call check_sizes(pattern, values, error, size(b), size(x))
        if (allocated(error)) return
        if (self%updated) then
            call refined_solve(self, pattern, values, b, x, error)
            return
        end if
        status = umfpack_di_solve(umfpack_a, pattern%colptr, pattern%rowind, values, x, b, &
                                  self%numeric, self%control, self%info)
        if (status /= umfpack_ok) then
            call fatal_error(error, 'solve failed: '//umfpack_status_text(int(status)), &
                             numerical_error)
        else if (allocated(self%base)) then
            self%b_base = b(1:pattern%n)
            self%x_base = x(1:pattern%n)
        end if
    end subroutine solve

    !> The updated solve with iterative refinement against the updated matrix `values`, as
    !> UMFPACK refines its own solves: while the sparse backward error (below) exceeds the
    !> unit round-off and at least halves, at most update_refinements steps; the best x is
    !> kept. A backward error still above update_omega_max is an error: the caller then
    !> factorises the matrix instead (factorise), so that an updated solve is never less
    !> accurate than UMFPACK's own.
    subroutine refined_solve(self, pattern, values, b, x, error)
        class(umfpack_t), intent(in) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:), b(:)
        real(dp), intent(out) :: x(:)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: r(:), dx(:), best(:)
        real(dp) :: omega, last, before
        integer :: step, n
        character(len=40) :: text
        n = pattern%n
        call self%solve_updated(pattern, b(1:n), x(1:n), error, load=.true.)
        if (allocated(error)) return
        allocate (r(n), dx(n))
        best = x(1:n)
        last = huge(1.0_dp)
        do step = 0, update_refinements
            omega = backward_error(pattern, values, b(1:n), x(1:n), r)
            if (.not. omega < last) exit
            before = last
            best = x(1:n)
            last = omega
            if (step == update_refinements .or. omega <= epsilon(1.0_dp)) exit
            if (step > 0 .and. omega > 0.5_dp*before) exit
            call self%solve_updated(pattern, r, dx, error)
            if (allocated(error)) return
            x(1:n) = x(1:n) + dx
        end do
        x(1:n) = best
        if (.not. last <= update_omega_max) then
            write (text, '(es9.2)') last
            call fatal_error(error, 'updated solve not accurate: backward error'//trim(text), &
                             numerical_error)
        end if
    end subroutine refined_solve

    !> UMFPACK's sparse backward error omega1 + omega2 of x for A x = b (Arioli, Demmel and
    !> Duff 1989), r = b - A x: row i counts |r_i| / (|A| |x| + |b|)_i where that is not
    !> tiny, else |r_i| / ((|A| |x| + |b|)_i + sum_j |A_ij| max |x|) (a row whose solution
    !> part is zero, as an open contact row's, would otherwise count round-off as 1).
    function backward_error(pattern, values, b, x, r) result(omega)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:), b(:), x(:)
        real(dp), intent(out) :: r(:)
        real(dp) :: omega
        real(dp), allocatable :: ax(:), row_sum(:)
        real(dp) :: xnorm, omega1, omega2, tau
        integer :: j, p, i, n
        n = pattern%n
        allocate (ax(n), row_sum(n), source=0.0_dp)
        r = b
        do j = 1, n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                i = pattern%rowind(p) + 1
                r(i) = r(i) - values(p)*x(j)
                ax(i) = ax(i) + abs(values(p)*x(j))
                row_sum(i) = row_sum(i) + abs(values(p))
            end do
        end do
        xnorm = maxval(abs(x))
        omega1 = 0.0_dp
        omega2 = 0.0_dp
        do i = 1, n
            tau = ax(i) + abs(b(i))
            if (tau > 1000.0_dp*n*epsilon(1.0_dp)*(row_sum(i)*xnorm + abs(b(i)))) then
                omega1 = max(omega1, abs(r(i))/tau)
            else if (tau + row_sum(i)*xnorm > 0.0_dp) then
                omega2 = max(omega2, abs(r(i))/(tau + row_sum(i)*xnorm))
            end if
        end do
        omega = omega1 + omega2
    end function backward_error

    !> UMFPACK's reciprocal condition estimate, min |U_ii| / max |U_ii|, of the last
    !> numeric factorisation.
    real(dp) function rcond(self)
        class(umfpack_t), intent(in) :: self
        rcond = self%info(i_rcond + 1)
    end function rcond

    !> Nonzeros of L + U of the last numeric factorisation (UMFPACK's fill; the unit
    !> diagonal of L not counted), 0 before the first.
    integer function factor_nonzeros(self)
        class(umfpack_t), intent(in) :: self
        factor_nonzeros = 0
        if (.not. c_associated(self%numeric)) return
        factor_nonzeros = nint(self%info(i_lnz + 1) + self%info(i_unz + 1) - &
                               self%info(i_nrow + 1))
    end function factor_nonzeros

    !> Free both factorisations (safe to call at any time).
    subroutine release(self)
        class(umfpack_t), intent(inout) :: self
        if (c_associated(self%numeric)) call umfpack_di_free_numeric(self%numeric)
        if (c_associated(self%symbolic)) call umfpack_di_free_symbolic(self%symbolic)
        self%numeric = c_null_ptr
        self%symbolic = c_null_ptr
        call self%forget_update()
        if (allocated(self%base)) deallocate (self%base)
        call self%free_spare()
    end subroutine release

    subroutine finalise(self)
        type(umfpack_t), intent(inout) :: self
        call self%release()
    end subroutine finalise

    !> The message of a singular or nearly singular system (UMFPACK's, or the contact
    !> system's reduced matrix in cfrd_schur): `what` the solver's finding, `rcond` its
    !> reciprocal condition estimate. The words "singular" are what the contact mechanism
    !> rule looks for (cfrd_linear_system's factorise_contact).
    function singular_text(what, rcond) result(text)
        character(len=*), intent(in) :: what
        real(dp), intent(in) :: rcond
        character(len=:), allocatable :: text
        character(len=120) :: numbers
        write (numbers, '(a,es9.2,a,es9.2,a)') ' (reciprocal condition estimate ', rcond, &
            ', limit ', rcond_min, ')'
        text = 'singular or nearly singular stiffness matrix: '//what//trim(numbers)// &
               '; is part of the mesh unsupported or disconnected?'
    end function singular_text

    !> The one place where UMFPACK status codes become words.
    pure function umfpack_status_text(status) result(text)
        integer, intent(in) :: status
        character(len=:), allocatable :: text
        select case (status)
        case (0)
            text = 'UMFPACK_OK'
        case (1)
            text = 'UMFPACK_WARNING_singular_matrix'
        case (2)
            text = 'UMFPACK_WARNING_determinant_underflow'
        case (3)
            text = 'UMFPACK_WARNING_determinant_overflow'
        case (-1)
            text = 'UMFPACK_ERROR_out_of_memory'
        case (-3)
            text = 'UMFPACK_ERROR_invalid_Numeric_object'
        case (-4)
            text = 'UMFPACK_ERROR_invalid_Symbolic_object'
        case (-5)
            text = 'UMFPACK_ERROR_argument_missing'
        case (-6)
            text = 'UMFPACK_ERROR_n_nonpositive'
        case (-8)
            text = 'UMFPACK_ERROR_invalid_matrix'
        case (-11)
            text = 'UMFPACK_ERROR_different_pattern'
        case (-13)
            text = 'UMFPACK_ERROR_invalid_system'
        case (-15)
            text = 'UMFPACK_ERROR_invalid_permutation'
        case (-17)
            text = 'UMFPACK_ERROR_file_IO'
        case (-18)
            text = 'UMFPACK_ERROR_ordering_failed'
        case (-911)
            text = 'UMFPACK_ERROR_internal_error'
        case default
            text = 'UMFPACK status unknown'
        end select
    end function umfpack_status_text
end module cfrd_umfpack
