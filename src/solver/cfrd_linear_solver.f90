!> The sparse direct solver of the stiffness equations (issue 21): CHOLMOD's supernodal
!> Cholesky factorisation (cfrd_cholmod) for a matrix that is symmetric with a positive
!> diagonal, UMFPACK's LU (cfrd_umfpack) for every other one and for every matrix CHOLMOD
!> declines (not positive definite, or its condition estimate below rcond_min): the same
!> matrix is then factorised by UMFPACK, no failure. The systems with contact multipliers
!> (saddle points, not positive definite) go to cfrd_schur when their K is symmetric with a
!> positive diagonal (CHOLMOD for K, a dense LU of the reduced system, which alone is
!> factorised again for a new active set), else to UMFPACK with its row updates.
!> `--linear-solver umfpack` forces UMFPACK everywhere (the solver before issue 21),
!> `--linear-solver cholmod` makes a symmetric system that CHOLMOD cannot factorise an
!> error instead of a fallback [choice] (docs/theory.md, "The linear solver").
module cfrd_linear_solver
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, numerical_error
    use cfrd_sparse, only: sparse_pattern_t
    use cfrd_umfpack, only: umfpack_t
    use cfrd_cholmod, only: cholmod_t, mirror_positions, symmetric_values, ordering_for
    use cfrd_schur, only: schur_t
    implicit none
    private

    public :: linear_solver_t
    public :: linear_solver_auto, linear_solver_cholmod, linear_solver_umfpack

    !> --linear-solver: CHOLMOD for the symmetric positive definite matrices and UMFPACK for
    !> the rest (auto, the default); CHOLMOD for every symmetric one, an error where it
    !> fails (cholmod); UMFPACK for all (umfpack).
    integer, parameter :: linear_solver_auto = 0, linear_solver_cholmod = 1, &
                          linear_solver_umfpack = 2

    !> The factorisation of one sparse matrix pattern, by CHOLMOD or UMFPACK.
    type :: linear_solver_t
        private
        type(umfpack_t) :: lu
        type(cholmod_t) :: llt
        integer :: choice = linear_solver_auto
        !> the system has no contact multipliers: its matrices may be positive definite
        logical :: may_be_spd = .true.
        !> the tangent is constant (linear laws): one factorisation per pattern, which
        !> decides CHOLMOD's ordering (cfrd_cholmod's ordering_for)
        logical :: constant_tangent = .false.
        integer, allocatable :: mirror(:)    !! mirror_positions of the pattern
        logical :: use_llt = .false.         !! the current matrix goes to CHOLMOD
        logical :: llt_factorised = .false.  !! the kept factorisation is CHOLMOD's
        logical :: lu_analysed = .false.
        !> A CHOLMOD factorisation set aside (keep) to be taken back (restore): the
        !> midpoint predictor's, at the start state of an increment that may be rejected
        type(cholmod_t) :: spare
        logical :: spare_factorised = .false.
        !> Saddle-point systems (contact): the last `multipliers` equations are multipliers;
        !> with K symmetric with a positive diagonal they go to CHOLMOD through K's Schur
        !> complement on the coupled equations (cfrd_schur), else to UMFPACK.
        integer :: multipliers = 0
        type(schur_t) :: sc
        logical :: use_schur = .false.       !! the current matrix goes to cfrd_schur
        !> the pattern's reduced matrix is above cfrd_schur's reduced_order_max: UMFPACK
        logical :: schur_too_large = .false.
        logical :: schur_factorised = .false.
    contains
        procedure :: configure
        procedure :: set_row_scaling
        procedure :: set_refinement
        procedure :: set_metis
        procedure :: choose
        procedure :: prepare
        procedure :: adopt
        procedure :: is_analysed
        procedure :: analyse
        procedure :: factorise
        procedure :: update_rows
        procedure :: solve
        procedure :: complete
        procedure :: rcond
        procedure :: factor_nonzeros
        procedure :: is_updated
        procedure :: is_cholesky
        procedure :: keep
        procedure :: restore
        procedure :: release
    end type linear_solver_t

contains

    !> The choice (linear_solver_auto, _cholmod, _umfpack), whether the system's
    !> matrices may be positive definite at all (false with contact multipliers), and
    !> whether its tangent is constant (factorised once per pattern; default false).
    !> `multipliers`: the number of trailing multiplier equations of a saddle-point system
    !> (0, the default: none).
    subroutine configure(self, choice, may_be_spd, constant_tangent, multipliers)
        class(linear_solver_t), intent(inout) :: self
        integer, intent(in) :: choice
        logical, intent(in) :: may_be_spd
        logical, intent(in), optional :: constant_tangent
        integer, intent(in), optional :: multipliers
        self%choice = choice
        self%may_be_spd = may_be_spd
        self%constant_tangent = .false.
        if (present(constant_tangent)) self%constant_tangent = constant_tangent
        self%multipliers = 0
        if (present(multipliers)) self%multipliers = multipliers
    end subroutine configure

    !> UMFPACK's row scaling (umfpack_t%set_row_scaling).
    subroutine set_row_scaling(self, on)
        class(linear_solver_t), intent(inout) :: self
        logical, intent(in) :: on
        call self%lu%set_row_scaling(on)
    end subroutine set_row_scaling

    !> UMFPACK's iterative refinement of the solves (umfpack_t%set_refinement; CHOLMOD's
    !> solves are not refined).
    subroutine set_refinement(self, on)
        class(linear_solver_t), intent(inout) :: self
        logical, intent(in) :: on
        call self%lu%set_refinement(on)
    end subroutine set_refinement

    !> UMFPACK's METIS ordering (umfpack_t%set_metis) from its next analysis on.
    subroutine set_metis(self, on)
        class(linear_solver_t), intent(inout) :: self
        logical, intent(in) :: on
        call self%lu%set_metis(on)
    end subroutine set_metis

    !> Which library factorises `values` next: CHOLMOD when the choice allows it and the
    !> matrix is symmetric with a positive diagonal (symmetric_values), else UMFPACK; a
    !> saddle-point system goes to cfrd_schur when its K is so (a Newton tangent is not:
    !> UMFPACK). Under --linear-solver cholmod a system without contact whose matrix is not
    !> so is an error.
    subroutine choose(self, pattern, values, error)
        class(linear_solver_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        self%use_llt = .false.
        self%use_schur = .false.
        if (self%choice == linear_solver_umfpack) return
        if (.not. self%may_be_spd .and. self%multipliers == 0) return
        if (allocated(self%mirror)) then
            if (size(self%mirror) /= pattern%nnz) deallocate (self%mirror)
        end if
        if (.not. allocated(self%mirror)) self%mirror = mirror_positions(pattern)
        if (self%multipliers > 0) then
            self%use_schur = .not. self%schur_too_large .and. &
                             symmetric_values(pattern, values, self%mirror, &
                                              pattern%n - self%multipliers)
            return
        end if
        self%use_llt = symmetric_values(pattern, values, self%mirror)
        if (.not. self%use_llt .and. self%choice == linear_solver_cholmod) &
            call fatal_error(error, 'the stiffness matrix is not symmetric with a positive '// &
                             'diagonal: CHOLMOD cannot factorise it (--linear-solver '// &
                             'cholmod; auto would use UMFPACK)', numerical_error)
    end subroutine choose

    !> The analyses that choose and analyse make of the pattern when its matrix is symmetric
    !> with a positive diagonal (CHOLMOD's, or cfrd_schur's for a saddle-point system), made
    !> before any values exist: a pattern prepared ahead (cfrd_linear_system), whose system
    !> adopts them. The same analyses, bit for bit, as those made when it is factorised.
    subroutine prepare(self, pattern, error)
        class(linear_solver_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        type(error_t), allocatable, intent(out) :: error
        logical :: fits
        if (self%choice == linear_solver_umfpack) return
        if (.not. self%may_be_spd .and. self%multipliers == 0) return
        self%mirror = mirror_positions(pattern)
        if (self%multipliers > 0) then
            call self%sc%analyse(pattern, self%multipliers, error, fits)
            if (.not. allocated(error)) self%schur_too_large = .not. fits
            return
        end if
        call self%llt%set_ordering(ordering_for(pattern%n, self%constant_tangent))
        call self%llt%analyse(pattern, error)
    end subroutine prepare

    !> The analyses prepared in `from` (prepare, on the same pattern and configuration)
    !> moved into self, released and configured: its factorisations need no analysis of
    !> their own. `from` is left released.
    subroutine adopt(self, from)
        class(linear_solver_t), intent(inout) :: self
        type(linear_solver_t), intent(inout) :: from
        if (allocated(from%mirror)) call move_alloc(from%mirror, self%mirror)
        if (from%llt%is_analysed()) call self%llt%exchange(from%llt)
        call self%sc%take_analysis(from%sc)
        self%schur_too_large = from%schur_too_large
        call from%release()
    end subroutine adopt

    !> The chosen library's symbolic analysis of the pattern exists.
    logical function is_analysed(self)
        class(linear_solver_t), intent(in) :: self
        if (self%use_schur) then
            is_analysed = self%sc%is_analysed()
        else if (self%use_llt) then
            is_analysed = self%llt%is_analysed()
        else
            is_analysed = self%lu_analysed
        end if
    end function is_analysed

    !> The chosen library's symbolic analysis (ordering) of the pattern.
    subroutine analyse(self, pattern, values, error)
        class(linear_solver_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        logical :: fits
        if (self%use_schur) then
            call self%sc%analyse(pattern, self%multipliers, error, fits)
            if (allocated(error) .or. fits) return
            ! too large a reduced matrix: this pattern's systems go to UMFPACK
            self%schur_too_large = .true.
            self%use_schur = .false.
        end if
        if (self%use_llt) then
            call self%llt%set_ordering(ordering_for(pattern%n, self%constant_tangent))
            call self%llt%analyse(pattern, error)
        else
            call self%lu%analyse(pattern, values, error)
            self%lu_analysed = .not. allocated(error)
        end if
    end subroutine analyse

    !> Numeric factorisation by the chosen library. `declined`: CHOLMOD found the matrix
    !> not positive definite (or too badly conditioned); UMFPACK is chosen now, and the
    !> caller factorises again (its analysis first, if is_analysed says so).
    subroutine factorise(self, pattern, values, declined, error, reused)
        class(linear_solver_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        logical, intent(out) :: declined
        type(error_t), allocatable, intent(out) :: error
        !> UMFPACK took back the factorisation set aside by keep: `values` is its matrix
        logical, intent(out), optional :: reused
        logical :: positive, again
        declined = .false.
        if (present(reused)) reused = .false.
        self%llt_factorised = .false.
        self%schur_factorised = .false.
        if (self%use_schur) then
            call self%sc%factorise(pattern, values, positive, error, again)
            if (present(reused)) reused = again
            if (allocated(error)) return
            self%schur_factorised = positive
            if (positive) return
            if (self%choice == linear_solver_cholmod) then
                call fatal_error(error, 'CHOLMOD: the contact system''s stiffness matrix K '// &
                                 '(its contact nodes'' diagonal shifted) is not positive '// &
                                 'definite, or its reciprocal condition estimate is below '// &
                                 'the limit (--linear-solver cholmod; auto would use '// &
                                 'UMFPACK)', numerical_error)
                return
            end if
            declined = .true.
            self%use_schur = .false.
            return
        end if
        if (self%use_llt) then
            call self%llt%factorise(pattern, values, positive, error)
            if (allocated(error)) return
            self%llt_factorised = positive
            if (positive) return
            if (self%choice == linear_solver_cholmod) then
                call fatal_error(error, 'CHOLMOD: the stiffness matrix is not positive '// &
                                 'definite, or its reciprocal condition estimate is below '// &
                                 'the limit (--linear-solver cholmod; auto would use UMFPACK)', &
                                 numerical_error)
                return
            end if
            declined = .true.
            self%use_llt = .false.
            return
        end if
        call self%lu%factorise(pattern, values, error, reused)
        if (.not. allocated(error)) self%lu_analysed = .true.
    end subroutine factorise

    !> UMFPACK's row update (umfpack_t%update_rows); never done on a CHOLMOD factorisation.
    !> `refused`: declined for a non-finite w or capacitance matrix.
    subroutine update_rows(self, pattern, values, done, error, refused)
        class(linear_solver_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        logical, intent(out) :: done
        type(error_t), allocatable, intent(out) :: error
        logical, intent(out), optional :: refused
        type(error_t), allocatable :: singular
        done = .false.
        if (present(refused)) refused = .false.
        if (self%schur_factorised) then
            ! the same K, new contact rows: R again (a singular R is factorise's to report)
            if (.not. self%sc%same_k(values)) return
            call self%sc%update(values, singular)
            done = .not. allocated(singular)
            self%schur_factorised = done
            return
        end if
        if (self%llt_factorised) return
        call self%lu%update_rows(pattern, values, done, error, refused)
    end subroutine update_rows

    !> x = A^-1 b with the kept factorisation (or UMFPACK's updated one).
    subroutine solve(self, pattern, values, b, x, error, partial)
        class(linear_solver_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:), b(:)
        real(dp), intent(out) :: x(:)
        type(error_t), allocatable, intent(out) :: error
        !> a contact system: the multipliers and the contact surfaces' displacements may
        !> come alone (cfrd_schur), the rest by `complete`
        logical, intent(in), optional :: partial
        if (self%schur_factorised) then
            call self%sc%solve(b, x, error, partial)
        else if (self%llt_factorised) then
            call self%llt%solve(b, x, error)
        else
            call self%lu%solve(pattern, values, b, x, error)
        end if
    end subroutine solve

    !> The displacements the last solve left out, when it was partial (cfrd_schur).
    subroutine complete(self, x, error)
        class(linear_solver_t), intent(inout) :: self
        real(dp), intent(inout) :: x(:)
        type(error_t), allocatable, intent(out) :: error
        if (self%schur_factorised) call self%sc%complete(x, error)
    end subroutine complete

    !> The reciprocal condition estimate of the kept factorisation's library.
    real(dp) function rcond(self)
        class(linear_solver_t), intent(in) :: self
        if (self%schur_factorised) then
            rcond = self%sc%rcond()
        else if (self%llt_factorised) then
            rcond = self%llt%rcond()
        else
            rcond = self%lu%rcond()
        end if
    end function rcond

    !> Nonzeros of the kept factorisation: L + U (UMFPACK), L (CHOLMOD).
    integer function factor_nonzeros(self)
        class(linear_solver_t), intent(in) :: self
        if (self%schur_factorised) then
            factor_nonzeros = self%sc%factor_nonzeros()
        else if (self%llt_factorised) then
            factor_nonzeros = self%llt%factor_nonzeros()
        else
            factor_nonzeros = self%lu%factor_nonzeros()
        end if
    end function factor_nonzeros

    logical function is_updated(self)
        class(linear_solver_t), intent(in) :: self
        is_updated = .false.
        if (.not. (self%llt_factorised .or. self%schur_factorised)) &
            is_updated = self%lu%is_updated()
    end function is_updated

    !> The kept factorisation is CHOLMOD's (cfrd_schur's included).
    logical function is_cholesky(self)
        class(linear_solver_t), intent(in) :: self
        is_cholesky = self%llt_factorised .or. self%schur_factorised
    end function is_cholesky

    !> Set the current factorisation aside when it is CHOLMOD's (`kept`), so that restore
    !> can take it back; the next one is factorised in the other CHOLMOD object, with a copy
    !> of the kept one's analysis the first time (the analysis depends on the pattern and
    !> the ordering alone: the same factors, bit for bit, without a second ordering).
    !> UMFPACK's is set aside too (umfpack_t%set_aside), not `kept`: factorise takes it
    !> back when it is given the same matrix again (the contact systems, whose matrix the
    !> caller assembles anew with the active set).
    subroutine keep(self, kept)
        class(linear_solver_t), intent(inout) :: self
        logical, intent(out) :: kept
        kept = self%llt_factorised
        if (self%schur_factorised) then
            ! taken back by factorise when the same K comes again (cfrd_schur's keep)
            call self%sc%keep()
            self%schur_factorised = .false.
            return
        end if
        if (.not. kept) then
            call self%lu%set_aside()
            return
        end if
        call self%llt%exchange(self%spare)
        if (.not. self%llt%is_analysed()) call self%llt%copy_analysis(self%spare)
        self%spare_factorised = .true.
        self%llt_factorised = .false.
    end subroutine keep

    !> Take back the factorisation set aside by keep: the solves are with it again.
    subroutine restore(self)
        class(linear_solver_t), intent(inout) :: self
        if (.not. self%spare_factorised) return
        call self%llt%exchange(self%spare)
        self%spare_factorised = .false.
        self%llt_factorised = .true.
        self%use_llt = .true.
    end subroutine restore

    !> Free both libraries' factorisations and the pattern's mirror (a new pattern follows).
    subroutine release(self)
        class(linear_solver_t), intent(inout) :: self
        call self%lu%release()
        call self%llt%release()
        call self%spare%release()
        call self%sc%release()
        self%spare_factorised = .false.
        self%use_schur = .false.
        self%schur_too_large = .false.
        self%schur_factorised = .false.
        if (allocated(self%mirror)) deallocate (self%mirror)
        self%use_llt = .false.
        self%llt_factorised = .false.
        self%lu_analysed = .false.
    end subroutine release

end module cfrd_linear_solver
