!> UMFPACK (SuiteSparse) for the stiffness equations, bound in two layers: private bind(C)
!> interfaces to the `umfpack_di_*` routines (int indices, double values), and a public
!> `umfpack_t` that keeps the symbolic factorisation for as long as the pattern holds, checks
!> every status, turns singularity into an error_t and frees its handles on every path.
module cfrd_umfpack
    use, intrinsic :: iso_c_binding, only: c_int, c_double, c_ptr, c_null_ptr, c_associated
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, numerical_error
    use cfrd_sparse, only: sparse_pattern_t
    implicit none
    private

    public :: umfpack_t, rcond_min, umfpack_status_text

    !> Below this reciprocal condition estimate the solution is refused: about 500 times the
    !> double-precision machine epsilon (2.2e-16). The error of a solve grows like eps/rcond, so
    !> below it fewer than three digits could be trusted; the estimate is of the row-scaled
    !> matrix, so it sees stiffness contrasts and rigid-body modes, not differences of units.
    real(dp), parameter :: rcond_min = 1.0e-13_dp

    ! Sizes and indices of umfpack.h (0-based in C, hence the +1 in Fortran).
    integer, parameter :: umfpack_control = 20, umfpack_info = 90
    integer, parameter :: i_prl = 0, i_strategy = 5, i_ordering = 10, i_scale = 16
    integer, parameter :: i_rcond = 67
    integer, parameter :: i_nrow = 1, i_lnz = 43, i_unz = 44
    integer(c_int), parameter :: ordering_amd = 1
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
    contains
        procedure :: set_row_scaling
        procedure :: analyse
        procedure :: factorise
        procedure :: solve
        procedure :: rcond
        procedure :: factor_nonzeros
        procedure :: release
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
    !> diagonal (docs/performance.md, table f). Takes effect at the next factorisation.
    subroutine set_row_scaling(self, on)
        class(umfpack_t), intent(inout) :: self
        logical, intent(in) :: on
        self%row_scaling = on
        if (self%configured) self%control(i_scale + 1) = &
            real(merge(scale_sum, scale_none, on), c_double)
    end subroutine set_row_scaling

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
    subroutine factorise(self, pattern, values, error)
        class(umfpack_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        integer(c_int) :: status
        character(len=120) :: text
        call check_sizes(pattern, values, error)
        if (allocated(error)) return
        if (.not. c_associated(self%symbolic)) then
            call self%analyse(pattern, values, error)
            if (allocated(error)) return
        end if
        if (c_associated(self%numeric)) call umfpack_di_free_numeric(self%numeric)
        status = umfpack_di_numeric(pattern%colptr, pattern%rowind, values, self%symbolic, &
                                    self%numeric, self%control, self%info)
        if (status == warning_singular .or. &
            (status == umfpack_ok .and. .not. (self%rcond() >= rcond_min))) then
            write (text, '(a,es9.2,a,es9.2,a)') ' (reciprocal condition estimate ', &
                self%rcond(), ', limit ', rcond_min, ')'
            call fatal_error(error, 'singular or nearly singular stiffness matrix: '// &
                             umfpack_status_text(int(status))//trim(text)// &
                             '; is part of the mesh unsupported or disconnected?', &
                             numerical_error)
        else if (status /= umfpack_ok) then
            call fatal_error(error, 'numeric factorisation failed: '// &
                             umfpack_status_text(int(status)), numerical_error)
        end if
        if (allocated(error)) then
            if (c_associated(self%numeric)) call umfpack_di_free_numeric(self%numeric)
            self%numeric = c_null_ptr
        end if
    end subroutine factorise

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
        status = umfpack_di_solve(umfpack_a, pattern%colptr, pattern%rowind, values, x, b, &
                                  self%numeric, self%control, self%info)
        if (status /= umfpack_ok) then
            call fatal_error(error, 'solve failed: '//umfpack_status_text(int(status)), &
                             numerical_error)
        end if
    end subroutine solve

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
    end subroutine release

    subroutine finalise(self)
        type(umfpack_t), intent(inout) :: self
        call self%release()
    end subroutine finalise

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
