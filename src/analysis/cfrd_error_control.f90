!> Error control of the midpoint and forward Euler increments (issue 21): an increment whose
!> relative out-of-balance force |f_k - f_int(sigma_new)| / |f_k| (the listing's MAX RESID)
!> exceeds ERRTOL is rejected (cfrd_increment returns it uncommitted, `unbalanced`), and the
!> stage driver redoes it from its start state in two halves, at most DEPTH halvings below
!> the stage's nominal increment, where it is accepted with a warning; the step grows back after an accepted one (docs/theory.md section 9,
!> "Error control").
module cfrd_error_control
    use cfrd_kinds, only: dp
    use cfrd_strings, only: to_text, real_text
    use cfrd_model, only: model_t, solver_newton
    implicit none
    private

    public :: out_of_tolerance, halvings, unbalanced_warning, may_grow

contains

    !> Whether an increment with relative residual `residual` is rejected: midpoint or Euler,
    !> ERRTOL > 0, and the residual above both ERRTOL and `roundoff` (the relative residual
    !> floating point resolves in the assembled forces, as for Newton's TOL).
    pure logical function out_of_tolerance(model, residual, roundoff)
        type(model_t), intent(in) :: model
        real(dp), intent(in) :: residual, roundoff
        out_of_tolerance = .false.
        if (model%solver == solver_newton .or. model%error_tolerance <= 0.0_dp) return
        out_of_tolerance = residual > max(model%error_tolerance, roundoff)
    end function out_of_tolerance

    !> Whether the step may double after an accepted increment of relative residual
    !> `residual`: always without error control (the Newton cutbacks grow back at once);
    !> under it only when the residual predicts that the doubled step stays below ERRTOL.
    !> The step rule of second-order error-controlled schemes, q = 0.9 (ERRTOL/residual)^(1/2)
    !> (Sloan, Abbo & Sheng 2001), reaches q = 2 at residual = 0.2 ERRTOL [lit; the halving
    !> and doubling in place of q itself: choice, docs/theory.md section 9].
    pure logical function may_grow(model, residual)
        type(model_t), intent(in) :: model
        real(dp), intent(in) :: residual
        may_grow = .true.
        if (model%solver == solver_newton .or. model%error_tolerance <= 0.0_dp) return
        may_grow = residual <= 0.2_dp*model%error_tolerance
    end function may_grow

    !> The halvings that took the nominal increment to `step` (both load fractions; the
    !> stage driver's steps are the nominal one over powers of 2, or the rest of the stage,
    !> counted as the power of 2 nearest to it).
    pure integer function halvings(step, nominal)
        real(dp), intent(in) :: step, nominal
        halvings = max(0, nint(log(nominal/step)/log(2.0_dp)))
    end function halvings

    !> The warning of an increment accepted above ERRTOL at the depth limit: where
    !> (context: stage, increment, load fraction), its residual and the depth.
    function unbalanced_warning(model, context, residual, depth) result(text)
        type(model_t), intent(in) :: model
        character(len=*), intent(in) :: context
        real(dp), intent(in) :: residual
        integer, intent(in) :: depth
        character(len=:), allocatable :: text
        text = context//': accepted out of balance above ERRTOL (relative residual '// &
               real_text(residual)//', ERRTOL '//real_text(model%error_tolerance)// &
               ') at subdivision depth '// &
               to_text(depth)//' (DEPTH of CONTROL ERRCTL; the residual is carried into '// &
               'the next increment)'
    end function unbalanced_warning

end module cfrd_error_control
