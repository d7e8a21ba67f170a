!> CHOLMOD (SuiteSparse) supernodal Cholesky factorisation L L^T for the symmetric positive
!> definite stiffness matrices (issue 21), bound in two layers: private bind(C) interfaces
!> to the functions of cfrd_cholmod_shim.c (which owns CHOLMOD's structs, whose layout
!> changes between versions), and a public `cholmod_t` that keeps the symbolic analysis
!> for as long as the pattern holds, reads the upper triangle of the full pattern that
!> cfrd assembles, and reports a matrix that is not positive definite (or too badly
!> conditioned) as declined, not as an error: the caller then factorises it by UMFPACK
!> (cfrd_linear_solver). `symmetric_values` says whether a matrix may go to it at all.
module cfrd_cholmod
    use, intrinsic :: iso_c_binding, only: c_int, c_double, c_ptr, c_null_ptr, c_associated
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, numerical_error
    use cfrd_sparse, only: sparse_pattern_t
    use cfrd_umfpack, only: rcond_min
    use cfrd_strings, only: to_text
    use cfrd_omp_threads, only: begin_serial_library, end_serial_library
    implicit none
    private

    public :: cholmod_t, mirror_positions, symmetric_values, ordering_for
    public :: ordering_amd, ordering_metis, ordering_nesdis, symmetry_tolerance

    !> CHOLMOD's ordering codes (cholmod_core.h).
    integer, parameter :: ordering_amd = 2, ordering_metis = 3, ordering_nesdis = 4
    !> |a_ij - a_ji| <= symmetry_tolerance sqrt(|a_ii a_jj|) at every entry: symmetric up to
    !> the round-off of the element matrices' products and their assembly [choice]. The
    !> bound is scaled by the diagonal (for an SPD matrix |a_ij| <= sqrt(a_ii a_jj)), so an
    !> entry that cancels to round-off in the assembly passes, while a Newton tangent's
    !> asymmetry (the consistent tangent of the E-B update, 1e-3 to 1 of its entries) or a
    !> contact system's does not. Such a matrix differs from its upper triangle by at most
    !> this relative amount: the solutions of the two differ by less than the 1e-8 the
    !> results are held to.
    real(dp), parameter :: symmetry_tolerance = 1.0e-12_dp

    !> Equations from which a varying tangent's pattern is ordered by nested dissection
    !> (ordering_for) [choice]: above every deck measured (docs/performance.md (y): AMD
    !> cost no more CPU time than NESDIS on every history up to 2e5 equations); NESDIS is
    !> left to larger meshes, where its fill saving grows, untested.
    integer, parameter :: nesdis_from = 250000

    ! cfrd_cholmod_shim.c's status codes (CHOLMOD's).
    integer(c_int), parameter :: cholmod_ok = 0, cholmod_not_posdef = 1

    !> A Cholesky factorisation of one sparse matrix pattern (its upper triangle).
    type :: cholmod_t
        private
        type(c_ptr) :: handle = c_null_ptr
        integer :: ordering = ordering_nesdis
        integer :: n = -1
        integer(c_int), allocatable :: up_colptr(:), up_rowind(:)
        integer, allocatable :: up_from(:)          !! position in the full pattern
        real(c_double), allocatable :: up_values(:)
        logical :: analysed = .false.
        logical :: factorised = .false.
    contains
        procedure :: set_ordering
        procedure :: analyse
        procedure :: copy_analysis
        procedure :: is_analysed
        procedure :: factorise
        procedure :: solve
        procedure :: permutation
        procedure :: tail
        procedure :: forward
        procedure :: backward
        procedure :: rcond
        procedure :: factor_nonzeros
        procedure :: release
        procedure :: exchange
        final :: finalise
    end type cholmod_t

    interface
        type(c_ptr) function cfrd_cholmod_new(ordering) bind(C, name='cfrd_cholmod_new')
            import :: c_int, c_ptr
            integer(c_int), value :: ordering
        end function cfrd_cholmod_new

        integer(c_int) function cfrd_cholmod_analyse(handle, n, ap, ai) &
            bind(C, name='cfrd_cholmod_analyse')
            import :: c_int, c_ptr
            type(c_ptr), value :: handle
            integer(c_int), value :: n
            integer(c_int), intent(in) :: ap(*), ai(*)
        end function cfrd_cholmod_analyse

        integer(c_int) function cfrd_cholmod_factorise(handle, ax) &
            bind(C, name='cfrd_cholmod_factorise')
            import :: c_int, c_double, c_ptr
            type(c_ptr), value :: handle
            real(c_double), intent(in) :: ax(*)
        end function cfrd_cholmod_factorise

        integer(c_int) function cfrd_cholmod_analyse_last(handle, n, ap, ai, last) &
            bind(C, name='cfrd_cholmod_analyse_last')
            import :: c_int, c_ptr
            type(c_ptr), value :: handle
            integer(c_int), value :: n
            integer(c_int), intent(in) :: ap(*), ai(*), last(*)
        end function cfrd_cholmod_analyse_last

        integer(c_int) function cfrd_cholmod_permutation(handle, perm) &
            bind(C, name='cfrd_cholmod_permutation')
            import :: c_int, c_ptr
            type(c_ptr), value :: handle
            integer(c_int), intent(out) :: perm(*)
        end function cfrd_cholmod_permutation

        integer(c_int) function cfrd_cholmod_tail(handle, tail, g, pivots) &
            bind(C, name='cfrd_cholmod_tail')
            import :: c_int, c_double, c_ptr
            type(c_ptr), value :: handle
            integer(c_int), value :: tail
            real(c_double), intent(out) :: g(*), pivots(2)
        end function cfrd_cholmod_tail

        integer(c_int) function cfrd_cholmod_forward(handle, b, z) &
            bind(C, name='cfrd_cholmod_forward')
            import :: c_int, c_double, c_ptr
            type(c_ptr), value :: handle
            real(c_double), intent(in) :: b(*)
            real(c_double), intent(out) :: z(*)
        end function cfrd_cholmod_forward

        integer(c_int) function cfrd_cholmod_backward(handle, z, x) &
            bind(C, name='cfrd_cholmod_backward')
            import :: c_int, c_double, c_ptr
            type(c_ptr), value :: handle
            real(c_double), intent(in) :: z(*)
            real(c_double), intent(out) :: x(*)
        end function cfrd_cholmod_backward

        real(c_double) function cfrd_cholmod_rcond(handle) bind(C, name='cfrd_cholmod_rcond')
            import :: c_double, c_ptr
            type(c_ptr), value :: handle
        end function cfrd_cholmod_rcond

        real(c_double) function cfrd_cholmod_factor_nonzeros(handle) &
            bind(C, name='cfrd_cholmod_factor_nonzeros')
            import :: c_double, c_ptr
            type(c_ptr), value :: handle
        end function cfrd_cholmod_factor_nonzeros

        integer(c_int) function cfrd_cholmod_solve(handle, b, x) &
            bind(C, name='cfrd_cholmod_solve')
            import :: c_int, c_double, c_ptr
            type(c_ptr), value :: handle
            real(c_double), intent(in) :: b(*)
            real(c_double), intent(out) :: x(*)
        end function cfrd_cholmod_solve

        type(c_ptr) function cfrd_cholmod_copy(from) bind(C, name='cfrd_cholmod_copy')
            import :: c_ptr
            type(c_ptr), value :: from
        end function cfrd_cholmod_copy

        subroutine cfrd_cholmod_free(handle) bind(C, name='cfrd_cholmod_free')
            import :: c_ptr
            type(c_ptr), value :: handle
        end subroutine cfrd_cholmod_free
    end interface

contains

    !> The fill-reducing ordering of the next analysis (ordering_amd, _metis, _nesdis).
    subroutine set_ordering(self, ordering)
        class(cholmod_t), intent(inout) :: self
        integer, intent(in) :: ordering
        if (self%ordering /= ordering) call self%release()
        self%ordering = ordering
    end subroutine set_ordering

    !> The fill-reducing ordering that pays for a pattern (docs/performance.md (y),
    !> docs/theory.md "The linear solver") [choice, measured]: AMD when its matrices have a
    !> constant tangent, factorised once per pattern: AMD's analysis costs a fraction of the
    !> nested dissection's (CHOLMOD's own default also starts from AMD and tries METIS only
    !> where AMD's fill is poor, cholmod_core.h `nmethods`) and its larger factor does not
    !> cost that back in one factorisation at any size measured (10^3 to 10^5 quads).
    !> For tangents that change every increment (tens of factorisations per pattern) AMD as
    !> well below `nesdis_from` equations (measured no dearer on every history up to 2e5
    !> equations), NESDIS from there on.
    pure integer function ordering_for(neq, constant_tangent) result(ordering)
        integer, intent(in) :: neq
        logical, intent(in) :: constant_tangent
        ordering = ordering_amd
        if (.not. constant_tangent .and. neq >= nesdis_from) ordering = ordering_nesdis
    end function ordering_for

    !> For each entry p of the pattern, the position of its transpose (0: none stored; a
    !> diagonal entry is its own).
    !> The rows of each column are sorted, so one pass over the columns in order finds them.
    pure function mirror_positions(pattern) result(mirror)
        type(sparse_pattern_t), intent(in) :: pattern
        integer, allocatable :: mirror(:)
        integer, allocatable :: next(:)
        integer :: i, j, p, q
        allocate (mirror(pattern%nnz), source=0)
        ! next(i): the first entry of column i whose row is not yet passed
        next = pattern%colptr(1:pattern%n) + 1
        do j = 1, pattern%n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                i = pattern%rowind(p) + 1
                if (i == j) mirror(p) = p
                if (i <= j) cycle
                ! entry (i, j) of the lower triangle: its transpose (j, i) in column i
                do q = next(i), pattern%colptr(i + 1)
                    if (pattern%rowind(q) + 1 >= j) exit
                end do
                next(i) = q
                if (q > pattern%colptr(i + 1)) cycle
                if (pattern%rowind(q) + 1 /= j) cycle
                mirror(p) = q
                mirror(q) = p
            end do
        end do
    end function mirror_positions

    !> Whether the matrix is symmetric to symmetry_tolerance with a positive diagonal (a
    !> necessary condition of positive definiteness; NaN fails). `mirror` is
    !> mirror_positions(pattern).
    pure logical function symmetric_values(pattern, values, mirror, leading) result(symmetric)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        integer, intent(in) :: mirror(:)
        !> only the leading block of this order (the K of a saddle-point system, cfrd_schur)
        integer, intent(in), optional :: leading
        !> symmetry_tolerance sqrt(a_ii): an entry's bound is the product of its row's and
        !> its column's, one square root per equation instead of one per entry
        real(dp), allocatable :: scale(:)
        integer :: i, j, p, n
        symmetric = .false.
        n = pattern%n
        if (present(leading)) n = min(leading, pattern%n)
        allocate (scale(n), source=0.0_dp)
        do j = 1, n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                if (pattern%rowind(p) + 1 == j) scale(j) = values(p)
            end do
        end do
        if (.not. all(scale > 0.0_dp)) return
        scale = sqrt(symmetry_tolerance)*sqrt(scale)
        do j = 1, n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                i = pattern%rowind(p) + 1
                if (i > n) exit
                if (i <= j) cycle
                if (mirror(p) == 0) then
                    if (.not. (abs(values(p)) <= scale(i)*scale(j))) return
                else if (.not. (abs(values(p) - values(mirror(p))) <= scale(i)*scale(j))) then
                    return
                end if
            end do
        end do
        ! an upper entry whose transpose is not stored
        do j = 1, n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                i = pattern%rowind(p) + 1
                if (i > n) exit
                if (i >= j .or. mirror(p) /= 0) cycle
                if (.not. (abs(values(p)) <= scale(i)*scale(j))) return
            end do
        end do
        symmetric = .true.
    end function symmetric_values

    !> Symbolic analysis (ordering, supernodes) of the upper triangle of the pattern;
    !> replaces an earlier one. With `last`, the columns where it is true are ordered after
    !> all the others (constrained minimum degree, CAMD; cfrd_schur), whatever the ordering
    !> set: the factor's last columns are then theirs (tail).
    subroutine analyse(self, pattern, error, last)
        class(cholmod_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in), optional :: last(:)
        integer :: j, p, k
        integer(c_int) :: status
        call self%release()
        self%handle = cfrd_cholmod_new(int(ordering_asked(self%ordering), c_int))
        if (.not. c_associated(self%handle)) then
            call fatal_error(error, 'CHOLMOD: out of memory', numerical_error)
            return
        end if
        self%n = pattern%n
        allocate (self%up_colptr(pattern%n + 1))
        k = 0
        do j = 1, pattern%n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                if (pattern%rowind(p) + 1 <= j) k = k + 1
            end do
        end do
        allocate (self%up_rowind(k), self%up_from(k), self%up_values(k))
        k = 0
        self%up_colptr(1) = 0
        do j = 1, pattern%n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                if (pattern%rowind(p) + 1 > j) cycle
                k = k + 1
                self%up_rowind(k) = pattern%rowind(p)
                self%up_from(k) = p
            end do
            self%up_colptr(j + 1) = k
        end do
        if (present(last)) then
            status = cfrd_cholmod_analyse_last(self%handle, int(pattern%n, c_int), &
                                               self%up_colptr, self%up_rowind, &
                                               merge(1_c_int, 0_c_int, last(1:pattern%n)))
        else
            status = cfrd_cholmod_analyse(self%handle, int(pattern%n, c_int), self%up_colptr, &
                                          self%up_rowind)
        end if
        if (status /= cholmod_ok) then
            call fatal_error(error, 'CHOLMOD: symbolic analysis failed (status '// &
                             status_text(status)//')', numerical_error)
            call self%release()
            return
        end if
        self%analysed = .true.
    end subroutine analyse

    !> The analysis of `from` (the same pattern and ordering) copied into self, whose own is
    !> released: the same factor as an analysis of its own, without the ordering's cost
    !> (cfrd_linear_solver's keep). Nothing is copied, and self is left without an
    !> analysis, when `from` has none or memory runs out: factorise then analyses.
    subroutine copy_analysis(self, from)
        class(cholmod_t), intent(inout) :: self
        type(cholmod_t), intent(in) :: from
        call self%release()
        if (.not. from%analysed) return
        self%handle = cfrd_cholmod_copy(from%handle)
        if (.not. c_associated(self%handle)) return
        self%analysed = .true.
        self%ordering = from%ordering
        self%n = from%n
        ! the upper triangle's pattern (its values are set by each factorise)
        self%up_colptr = from%up_colptr
        self%up_rowind = from%up_rowind
        self%up_from = from%up_from
    end subroutine copy_analysis

    logical function is_analysed(self)
        class(cholmod_t), intent(in) :: self
        is_analysed = self%analysed
    end function is_analysed

    !> Numeric factorisation of the upper triangle of `values` (a matrix of the analysed
    !> pattern). `positive` is false, and no factorisation is kept, when CHOLMOD finds it
    !> not positive definite or its reciprocal condition estimate is below rcond_min (the
    !> caller then factorises it by UMFPACK, whose verdict on a singular matrix stands).
    subroutine factorise(self, pattern, values, positive, error)
        class(cholmod_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        logical, intent(out) :: positive
        type(error_t), allocatable, intent(out) :: error
        integer(c_int) :: status
        integer :: levels
        positive = .false.
        self%factorised = .false.
        if (.not. self%analysed) call self%analyse(pattern, error)
        if (allocated(error)) return
        if (pattern%n /= self%n .or. size(values) < pattern%nnz .or. &
            maxval([0, self%up_from]) > pattern%nnz) then
            call fatal_error(error, 'internal: CHOLMOD given a matrix of another pattern', &
                             numerical_error)
            return
        end if
        self%up_values = values(self%up_from)
        levels = begin_serial_library()     ! CHOLMOD's own OpenMP loops on this thread
        status = cfrd_cholmod_factorise(self%handle, self%up_values)
        call end_serial_library(levels)
        if (status == cholmod_not_posdef) return
        if (status /= cholmod_ok) then
            call fatal_error(error, 'CHOLMOD: numeric factorisation failed (status '// &
                             status_text(status)//')', numerical_error)
            return
        end if
        positive = self%rcond() >= rcond_min
        self%factorised = positive
    end subroutine factorise

    !> x = A^-1 b with the kept factorisation.
    subroutine solve(self, b, x, error)
        class(cholmod_t), intent(inout) :: self
        real(dp), intent(in) :: b(:)
        real(dp), intent(out) :: x(:)
        type(error_t), allocatable, intent(out) :: error
        integer(c_int) :: status
        if (.not. self%factorised) then
            call fatal_error(error, 'internal: CHOLMOD solve called without a factorisation', &
                             numerical_error)
            return
        end if
        if (size(b) < self%n .or. size(x) < self%n) then
            call fatal_error(error, 'internal: vector shorter than the CHOLMOD matrix', &
                             numerical_error)
            return
        end if
        status = cfrd_cholmod_solve(self%handle, b, x)
        if (status /= cholmod_ok) call fatal_error(error, 'CHOLMOD: solve failed (status '// &
                                                   status_text(status)//')', numerical_error)
    end subroutine solve

    !> The analysis's permutation: perm(k) is the equation (1-based) in the factor's
    !> position k.
    subroutine permutation(self, perm, error)
        class(cholmod_t), intent(in) :: self
        integer, allocatable, intent(out) :: perm(:)
        type(error_t), allocatable, intent(out) :: error
        integer(c_int), allocatable :: p0(:)
        if (.not. self%analysed) then
            call fatal_error(error, 'internal: CHOLMOD permutation without an analysis', &
                             numerical_error)
            return
        end if
        allocate (p0(self%n))
        if (cfrd_cholmod_permutation(self%handle, p0) /= cholmod_ok) then
            call fatal_error(error, 'internal: CHOLMOD permutation failed', numerical_error)
            return
        end if
        perm = p0 + 1
    end subroutine permutation

    !> The factor's last `ntail` columns (all of whose rows are among them) as a dense lower
    !> triangle g(ntail, ntail), and the smallest and largest L_jj^2 of the columns before
    !> them (`pivots`; 0 when there are none).
    subroutine tail(self, ntail, g, pivots, error)
        class(cholmod_t), intent(in) :: self
        integer, intent(in) :: ntail
        real(dp), intent(out) :: g(:, :), pivots(2)
        type(error_t), allocatable, intent(out) :: error
        if (.not. self%factorised .or. size(g, 1) /= ntail .or. size(g, 2) /= ntail) then
            call fatal_error(error, 'internal: CHOLMOD tail without a factorisation', &
                             numerical_error)
            return
        end if
        if (cfrd_cholmod_tail(self%handle, int(ntail, c_int), g, pivots) /= cholmod_ok) &
            call fatal_error(error, 'internal: CHOLMOD tail of a factor that is not '// &
                             'supernodal L L^T', numerical_error)
    end subroutine tail

    !> The first half of a solve: z = L^-1 P b, z in the factor's order.
    subroutine forward(self, b, z, error)
        class(cholmod_t), intent(inout) :: self
        real(dp), intent(in) :: b(:)
        real(dp), intent(out) :: z(:)
        type(error_t), allocatable, intent(out) :: error
        call half_check(self, size(b), size(z), error)
        if (allocated(error)) return
        if (cfrd_cholmod_forward(self%handle, b, z) /= cholmod_ok) &
            call fatal_error(error, 'CHOLMOD: forward solve failed', numerical_error)
    end subroutine forward

    !> The second half of a solve: x = P^T L^-T z.
    subroutine backward(self, z, x, error)
        class(cholmod_t), intent(inout) :: self
        real(dp), intent(in) :: z(:)
        real(dp), intent(out) :: x(:)
        type(error_t), allocatable, intent(out) :: error
        call half_check(self, size(z), size(x), error)
        if (allocated(error)) return
        if (cfrd_cholmod_backward(self%handle, z, x) /= cholmod_ok) &
            call fatal_error(error, 'CHOLMOD: backward solve failed', numerical_error)
    end subroutine backward

    subroutine half_check(self, n_in, n_out, error)
        type(cholmod_t), intent(in) :: self
        integer, intent(in) :: n_in, n_out
        type(error_t), allocatable, intent(out) :: error
        if (.not. self%factorised) then
            call fatal_error(error, 'internal: CHOLMOD solve called without a factorisation', &
                             numerical_error)
        else if (n_in < self%n .or. n_out < self%n) then
            call fatal_error(error, 'internal: vector shorter than the CHOLMOD matrix', &
                             numerical_error)
        end if
    end subroutine half_check

    !> CHOLMOD's reciprocal condition estimate (min L_jj / max L_jj)^2, 0 before a
    !> factorisation.
    real(dp) function rcond(self)
        class(cholmod_t), intent(in) :: self
        rcond = 0.0_dp
        if (c_associated(self%handle)) rcond = cfrd_cholmod_rcond(self%handle)
    end function rcond

    !> Nonzeros of L (its diagonal counted), 0 before an analysis.
    integer function factor_nonzeros(self)
        class(cholmod_t), intent(in) :: self
        factor_nonzeros = 0
        if (c_associated(self%handle)) &
            factor_nonzeros = nint(cfrd_cholmod_factor_nonzeros(self%handle))
    end function factor_nonzeros

    !> Free the analysis and the factorisation (safe to call at any time).
    subroutine release(self)
        class(cholmod_t), intent(inout) :: self
        if (c_associated(self%handle)) call cfrd_cholmod_free(self%handle)
        self%handle = c_null_ptr
        self%analysed = .false.
        self%factorised = .false.
        self%n = -1
        if (allocated(self%up_colptr)) deallocate (self%up_colptr)
        if (allocated(self%up_rowind)) deallocate (self%up_rowind, self%up_from)
        if (allocated(self%up_values)) deallocate (self%up_values)
    end subroutine release

    !> Exchange the analyses and factorisations of two objects, freeing neither (a
    !> factorisation set aside and taken back, cfrd_linear_solver's keep and restore).
    subroutine exchange(self, other)
        class(cholmod_t), intent(inout) :: self
        type(cholmod_t), intent(inout) :: other
        type(c_ptr) :: handle
        integer(c_int), allocatable :: colptr(:), rowind(:)
        integer, allocatable :: from(:)
        real(c_double), allocatable :: values(:)
        integer :: numbers(2)
        logical :: flags(2)
        handle = self%handle
        numbers = [self%ordering, self%n]
        flags = [self%analysed, self%factorised]
        call move_alloc(self%up_colptr, colptr)
        call move_alloc(self%up_rowind, rowind)
        call move_alloc(self%up_from, from)
        call move_alloc(self%up_values, values)
        self%handle = other%handle
        self%ordering = other%ordering
        self%n = other%n
        self%analysed = other%analysed
        self%factorised = other%factorised
        call move_alloc(other%up_colptr, self%up_colptr)
        call move_alloc(other%up_rowind, self%up_rowind)
        call move_alloc(other%up_from, self%up_from)
        call move_alloc(other%up_values, self%up_values)
        other%handle = handle
        other%ordering = numbers(1)
        other%n = numbers(2)
        other%analysed = flags(1)
        other%factorised = flags(2)
        call move_alloc(colptr, other%up_colptr)
        call move_alloc(rowind, other%up_rowind)
        call move_alloc(from, other%up_from)
        call move_alloc(values, other%up_values)
    end subroutine exchange

    subroutine finalise(self)
        type(cholmod_t), intent(inout) :: self
        call self%release()
    end subroutine finalise

    !> CFRD_CHOLMOD_ORDERING=amd|metis|nesdis (a measuring aid, like CFRD_WRITE_MATRIX;
    !> docs/performance.md (o)): that ordering instead of `ordering`.
    integer function ordering_asked(ordering) result(chosen)
        integer, intent(in) :: ordering
        character(len=16) :: text
        integer :: length, status
        chosen = ordering
        call get_environment_variable('CFRD_CHOLMOD_ORDERING', text, length, status)
        if (status /= 0) return
        select case (text)
        case ('amd')
            chosen = ordering_amd
        case ('metis')
            chosen = ordering_metis
        case ('nesdis')
            chosen = ordering_nesdis
        end select
    end function ordering_asked

    pure function status_text(status) result(text)
        integer(c_int), intent(in) :: status
        character(len=:), allocatable :: text
        text = to_text(int(status))
        select case (status)
        case (-2)
            text = text//', out of memory'
        case (-3)
            text = text//', too large'
        case (-4)
            text = text//', invalid input'
        end select
    end function status_text

end module cfrd_cholmod
