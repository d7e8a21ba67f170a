!> One increment of a stage, solved: the predictor with the tangent at its start, the
!> midpoint (modified Euler) corrector, forward Euler, or Newton iterations with the
!> consistent tangent and a line search (docs/theory.md sections 9 and 12); the stress
!> update of every Gauss point, the out-of-balance force, and the acceptance of the
!> increment into the state. With contact, the geometry is updated first and each solve
!> iterates the active set (cfrd_active_set).
module cfrd_increment
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, numerical_error
    use cfrd_clock, only: wall_seconds
    use cfrd_strings, only: to_text, real_text
    use cfrd_model, only: model_t, solver_midpoint, solver_euler, solver_newton
    use cfrd_results, only: stage_result_t
    use cfrd_material_law, only: all_linear, update_history, material_update, &
                                 material_update_tangent, material_tangent, update_substeps, &
                                 material_update_with_tangent
    use cfrd_assembly, only: element_box_t, dof_map_t, assemble_tangent, internal_forces, &
                             gather, min_parallel, remembered_forces, remember_forces
    use cfrd_contact, only: contact_t, contact_geometry
    use cfrd_contact_constraints, only: contact_forces, contact_accept, contact_shear_shape
    use cfrd_linear_system, only: system_t, new_system, factorise_values, factorise_contact, &
                                  multiplier_scale
    use cfrd_active_set, only: solve_system
    use cfrd_stage_state, only: state_t, ngauss
    use cfrd_error_control, only: out_of_tolerance
    use cfrd_krylov, only: gmres_solve
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    !> Newton's corrections by GMRES with the kept factorisation (newton_correction): the
    !> relative residual |r - A ddu| / |r| they are solved to, about that of a direct solve
    !> without refinement (docs/performance.md (k): up to 3e-13) [choice]; and the most
    !> GMRES iterations before A is factorised instead, about the cost of one numeric
    !> factorisation in preconditioner solves (docs/performance.md (z)) [choice].
    real(dp), parameter :: krylov_rtol = 1.0e-12_dp
    real(dp), parameter :: krylov_rtol_max = 1.0e-8_dp
    real(dp), parameter :: krylov_share = 1.0e-3_dp
    real(dp), parameter :: krylov_residual = 1.0e-4_dp
    integer, parameter :: krylov_iterations = 10

    public :: solve_increment, integrate_stress, accept_history, all_linear, newton_stalled

contains

    !> Assemble the tangent at the given stresses and factorise it (numeric phase only while
    !> the pattern holds). A constant (linear elastic) tangent is factorised once per system.
    !> With contact (`contact` present), K is kept apart and the contact rows of the current
    !> active set are added before each factorisation (factorise_contact).
    subroutine factorise_at(model, library, state, stress, system, result, context, error, &
                            tangents, contact)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        real(dp), intent(in) :: stress(:, :, :)
        type(system_t), intent(inout) :: system
        type(stage_result_t), intent(inout) :: result
        character(len=*), intent(in) :: context
        type(error_t), allocatable, intent(out) :: error
        real(dp), intent(in), optional :: tangents(:, :, :, :)
        type(contact_t), intent(in), optional :: contact
        real(dp) :: t0, t1
        logical :: linear, assembled_before
        linear = all_linear(model, state%active)
        if (present(contact)) then
            assembled_before = allocated(system%k_values)
            if (.not. (linear .and. allocated(system%k_values))) then
                t0 = wall_seconds()
                call assemble_tangent(model, library, state%active, system%pattern, stress, &
                                      state%strain, state%history, system%values, tangents)
                if (.not. (allocated(system%k_values) .or. system%scale_given)) &
                    system%contact_scale = multiplier_scale(system, contact)
                system%scale_given = .false.
                system%k_values = system%values
                result%stats%t_assembly = result%stats%t_assembly + (wall_seconds() - t0)
            end if
            ! K alone unchanged (linear, assembled already): only contact rows can differ
            call factorise_contact(model, system, contact, result, context, error, &
                                   linear .and. assembled_before)
            return
        end if
        if (linear .and. system%factorised_linear) return
        t0 = wall_seconds()
        call assemble_tangent(model, library, state%active, system%pattern, stress, &
                              state%strain, state%history, system%values, tangents)
        t1 = wall_seconds()
        result%stats%t_assembly = result%stats%t_assembly + (t1 - t0)
        call factorise_values(system, result, context, error)
        system%factorised_linear = linear
    end subroutine factorise_at

    !> One increment to the external load `f_target`: the right-hand side is the out-of-
    !> balance force f_target - f_int(sigma_n), so that the residual left by earlier increments
    !> is carried into this one (equilibrium correction). With contact, the geometry is
    !> updated first (the paper's Step 6) and each solve iterates the active set; the contact
    !> state changes only when the increment is accepted.
    subroutine solve_increment(model, library, state, system, f_target, du_prescribed, &
                               result, context, error, accepted_residual, may_reject, &
                               unbalanced, stalled)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(inout) :: state
        type(system_t), intent(inout) :: system
        real(dp), intent(in) :: f_target(:, :)
        real(dp), intent(in) :: du_prescribed(:, :)   !! increment of prescribed displacements
        type(stage_result_t), intent(inout) :: result
        character(len=*), intent(in) :: context
        type(error_t), allocatable, intent(out) :: error
        !> the relative residual of the increment (MAX RESID's measure)
        real(dp), intent(out), optional :: accepted_residual
        !> midpoint / Euler: an increment above ERRTOL is rejected, returned with nothing of
        !> the state changed (the stage driver halves it); absent or false (the error
        !> control's depth limit), it is accepted and `unbalanced` says so
        logical, intent(in), optional :: may_reject
        !> the increment is above ERRTOL (rejected when may_reject, else accepted)
        logical, intent(out), optional :: unbalanced
        !> the error is a convergence failure (Newton's iterations, the contact active set),
        !> which a smaller step may cure: the stage driver cuts the increment back
        logical, intent(out), optional :: stalled
        real(dp), allocatable :: du(:, :), stress_end(:, :, :), stress_mid(:, :, :)
        real(dp) :: residual, load_norm, t0, floor
        real(dp), allocatable :: rhs_stress(:, :, :), d_start(:, :, :, :), f_end(:, :)
        real(dp), allocatable :: d_here(:, :, :, :)
        integer, allocatable :: substeps(:, :), grown(:, :)
        !> the consistent tangents of the last full Newton step taken (consistent_tangents)
        real(dp), allocatable :: c_next(:, :, :, :)
        integer :: iteration
        type(contact_t), allocatable :: contact
        logical :: changed, searched, linear, reject, reuse, retried

        if (present(unbalanced)) unbalanced = .false.
        if (present(stalled)) stalled = .false.
        load_norm = max(norm2(f_target), tiny(1.0_dp))
        system%viscous = 0.0_dp
        if (state%has_contact) then
            contact = state%contact
            t0 = wall_seconds()
            call contact_geometry(model, state%active, contact, changed, searched)
            call contact_shear_shape(contact)
            result%stats%t_contact = result%stats%t_contact + (wall_seconds() - t0)
            if (changed) then
                t0 = wall_seconds()
                call new_system(model, library, state%active, system, error, contact, .true.)
                if (allocated(error)) return
                result%stats%t_pattern = result%stats%t_pattern + (wall_seconds() - t0)
                result%stats%patterns = result%stats%patterns + 1
                result%stats%neq = system%pattern%n
                result%stats%nnz = system%pattern%nnz
            end if
        end if
        ! Predictor with the tangent at the start of the increment; a rejected midpoint
        ! increment (error control) or a Newton increment cut back, redone from the same
        ! state, takes back the factorisation of that tangent kept from its first attempt:
        ! CHOLMOD's by restore (`reuse`, without contact); with contact in factorise_at,
        ! K's (cfrd_schur) when K assembled again is the same, UMFPACK's when the whole
        ! matrix is, bit for bit (linear_solver_t%keep).
        retried = model%solver == solver_newton .or. &
                  (model%solver == solver_midpoint .and. model%error_tolerance > 0.0_dp)
        reuse = .not. state%has_contact .and. retried
        ! The tangents at the start stresses once (docs/performance.md (v)): the predictor's
        ! matrix, the updates from the start stress and Newton's iterations (newton_start)
        ! take these. Not with creep, whose updates start elsewhere (absent, each caller
        ! evaluates its own as before).
        if (.not. (allocated(state%creep_stress) .or. all_linear(model, state%active))) &
            d_here = start_tangents(model, library, state)
        if (reuse .and. system%start_kept) then
            call system%solver%restore()
            system%start_kept = .false.
        else
            call factorise_at(model, library, state, state%stress, system, result, context, &
                              error, d_here, contact)
            if (allocated(error)) return
        end if
        ! With creep the start stresses less the stresses the increment's creep relaxes: the
        ! creep load joins the out-of-balance force (cfrd_creep_step).
        rhs_stress = state%stress
        if (allocated(state%creep_stress)) rhs_stress = rhs_stress - state%creep_stress
        call solve_out_of_balance(model, library, state, rhs_stress, f_target, du_prescribed, &
                                  system, du, result, context, error, contact, unsettled=stalled)
        if (allocated(error)) return
        linear = system%factorised_linear .or. &
                 (state%has_contact .and. all_linear(model, state%active))
        if (model%solver == solver_euler .or. linear) then
            ! Euler; or a linear law, for which the midpoint step would repeat the same solve.
            ! Forward Euler's own stresses balance the load (the update uses the solve's
            ! tangent): under error control the stresses of the increment are the midpoint
            ! update's, whose residual is the Euler / modified-Euler difference of Sloan
            ! (1987), accepted with local extrapolation as there (docs/theory.md section 9).
            call integrate_stress(model, library, state, du, stress_end, stress_mid, &
                                  model%solver == solver_euler .and. &
                                  model%error_tolerance > 0.0_dp, creep_share=1.0_dp, &
                                  d_start=d_here)
        else
            ! Midpoint: stresses half-way, the tangent there, and the increment again.
            call integrate_stress(model, library, state, 0.5_dp*du, stress_mid, stress_end, &
                                  .false., creep_share=0.5_dp, d_start=d_here)
            if (retried) call system%solver%keep(system%start_kept)
            call factorise_at(model, library, state, stress_mid, system, result, context, &
                              error, contact=contact)
            if (allocated(error)) return
            call solve_out_of_balance(model, library, state, rhs_stress, f_target, &
                                      du_prescribed, system, du, result, context, error, &
                                      contact, unsettled=stalled)
            if (allocated(error)) return
            if (model%solver == solver_newton) then
                ! The counts first, so that the predictor's stresses are updated once (with
                ! one sub-step a point's update is the plain midpoint one, bit for bit).
                call newton_start(model, library, state, du, d_start, substeps, d_here)
                call integrate_stress(model, library, state, du, stress_end, stress_mid, &
                                      .true., creep_share=1.0_dp, d_start=d_start, &
                                      substeps=substeps)
            else
                call integrate_stress(model, library, state, du, stress_end, stress_mid, &
                                      .true., creep_share=1.0_dp, d_start=d_here)
            end if
        end if
        if (model%solver == solver_newton .and. .not. allocated(substeps)) then
            call newton_start(model, library, state, du, d_start, substeps, d_here)
            if (any(substeps > 1)) &
                call integrate_stress(model, library, state, du, stress_end, stress_mid, &
                                      .true., creep_share=1.0_dp, d_start=d_start, &
                                      substeps=substeps)
        end if
        residual = out_of_balance(model, library, state%active, stress_end, f_target, &
                                  system%dofmap, contact, roundoff=floor, force=f_end)/load_norm
        if (model%solver == solver_newton) then
            result%newton_residuals = [residual]
            iteration = 0
            ! Converged when the residual relative to the whole model's load is below TOL, or
            ! below what floating point resolves in the assembled forces (docs/theory.md
            ! section 9.3): a TOL under round-off cannot stall the iterations.
            do while (residual > max(model%tolerance, floor/load_norm))
                iteration = iteration + 1
                ! A stall ends the iterations early, so that a cutback can be tried without
                ! waste (newton_stalled).
                if (newton_stalled(result%newton_residuals(1:iteration))) then
                    call fatal_error(error, context//': no convergence: Newton '// &
                                     'iterations stalled at iteration '// &
                                     to_text(iteration - 1)//' (relative residual '// &
                                     real_text(residual)//', tolerance '// &
                                     real_text(model%tolerance)//'; largest out-of-'// &
                                     'balance force at '//worst_node()//')', &
                                     numerical_error)
                    if (present(stalled)) stalled = .true.
                    return
                end if
                if (iteration > model%max_iterations) then
                    call fatal_error(error, context//': no convergence after '// &
                                     to_text(model%max_iterations)//' Newton iterations '// &
                                     '(relative residual '//real_text(residual)//', tolerance '// &
                                     real_text(model%tolerance)//'; largest out-of-balance '// &
                                     'force at '//worst_node()//')', numerical_error)
                    if (present(stalled)) stalled = .true.
                    return
                end if
                ! More sub-steps where du now asks for them: the stresses and the residual
                ! of du again with those (the update is another function of du now).
                grown = substep_counts(model, library, state, du, d_start, substeps)
                if (any(grown /= substeps)) then
                    substeps = grown
                    if (allocated(c_next)) deallocate (c_next)
                    call integrate_stress(model, library, state, du, stress_end, stress_mid, &
                                          .true., creep_share=1.0_dp, d_start=d_start, &
                                          substeps=substeps)
                    residual = out_of_balance(model, library, state%active, stress_end, &
                                              f_target, system%dofmap, contact, &
                                              roundoff=floor, force=f_end)/load_norm
                end if
                block
                    real(dp), allocatable :: ddu(:, :), du_try(:, :), stress_try(:, :, :), &
                                             f_try(:, :), c(:, :, :, :), c_try(:, :, :, :)
                    real(dp) :: step, trial
                    integer :: halving
                    ! The consistent tangent: the derivative of the midpoint stress update
                    ! with respect to the strain increment at each point
                    ! (material_update_tangent); the correction for f_target - f_int(stress_end)
                    ! (the internal forces of the residual above).
                    ! The tangent at du: the last full step's, when it was taken
                    ! (consistent_tangents with the update), else evaluated here.
                    if (allocated(c_next)) then
                        call move_alloc(c_next, c)
                    else
                        call consistent_tangents(model, library, state, du, d_start, substeps, c)
                    end if
                    if (state%has_contact .or. all_linear(model, state%active)) then
                        call factorise_at(model, library, state, stress_mid, system, result, &
                                          context, error, c, contact)
                        if (allocated(error)) return
                        call solve_system(model, f_target - f_end, 0.0_dp*du_prescribed, &
                                          system, ddu, result, context, error, contact, du, &
                                          stalled)
                    else
                        call newton_correction(model, library, state, stress_mid, c, &
                                               f_target - f_end, residual, &
                                               iteration == 1, system, ddu, result, &
                                               context, error)
                    end if
                    deallocate (c)
                    if (allocated(error)) return
                    ! Backtracking line search: the E-B tangent has kinks (stress-level cap,
                    ! sigma3 floor, Poisson bounds, unloading transition) where a full
                    ! Newton step can overshoot; halve it while the residual grows. Not with
                    ! contact: the multipliers belong to the full step.
                    step = 1.0_dp
                    do halving = 0, 6
                        du_try = du + step*ddu
                        if (halving == 0) then
                            ! The full step with its tangent, the next iteration's if taken
                            call consistent_tangents(model, library, state, du_try, d_start, &
                                                     substeps, c_try, stress_try, stress_mid)
                        else
                            call integrate_stress(model, library, state, du_try, stress_try, &
                                                  stress_mid, .true., creep_share=1.0_dp, &
                                                  d_start=d_start, substeps=substeps)
                        end if
                        trial = out_of_balance(model, library, state%active, stress_try, &
                                               f_target, system%dofmap, contact, &
                                               roundoff=floor, force=f_try)/load_norm
                        if (trial < residual .or. state%has_contact) exit
                        step = 0.5_dp*step
                    end do
                    du = du_try
                    stress_end = stress_try
                    f_end = f_try
                    residual = trial
                    if (halving == 0) call move_alloc(c_try, c_next)
                end block
                result%iterations = result%iterations + 1
                result%newton_residuals = [result%newton_residuals, residual]
            end do
        end if
        if (.not. (residual < huge(1.0_dp))) then
            call fatal_error(error, context//': the solution is not finite', numerical_error)
            return
        end if
        ! Midpoint and Euler: an increment out of balance beyond ERRTOL is not accepted
        ! (cfrd_error_control; the stage driver halves it). Not where every active law is
        ! linear: the update is exact, and what residual there is (round-off against a load
        ! that may pass through zero, the contact's) is no error of the step's size.
        reject = .not. linear .and. out_of_tolerance(model, residual, floor/load_norm)
        if (present(unbalanced)) unbalanced = reject
        if (present(accepted_residual)) accepted_residual = residual
        if (present(may_reject)) then
            if (reject .and. may_reject) return
        end if
        ! Searches are counted for the increments accepted (a rejected one searches again).
        if (state%has_contact) then
            if (searched) result%stats%searches = result%stats%searches + 1
        end if
        system%start_kept = .false.
        call remember_forces(system%forces, state%active, stress_end, f_end)
        state%u = state%u + du
        state%stress = stress_end
        state%f_ext = f_target
        call accept_history(model, library, state, du)
        if (state%has_contact) then
            state%contact = contact
            call contact_accept(state%contact, du)
        end if
        result%max_residual = max(result%max_residual, residual)
    contains
        function worst_node() result(text)
            character(len=:), allocatable :: text
            real(dp) :: norm
            norm = out_of_balance(model, library, state%active, stress_end, f_target, &
                                  system%dofmap, contact, text)
        end function worst_node
    end subroutine solve_increment

    !> Whether Newton's iterations have stalled, given the relative residuals r_0 .. r_i of
    !> the increment so far (r(1) = r_0, the predictor's; i >= 4): every fourth iteration
    !> (i = 4, 8, ...) when r_i > r_i-4 / 2, the residual not halved over the last four;
    !> at every iteration when none of r_i-3 .. r_i is below r_i-4 / 2 (docs/theory.md
    !> section 9, "Stalls").
    pure logical function newton_stalled(r) result(stalled)
        real(dp), intent(in) :: r(:)
        integer :: n
        n = size(r)   ! r_i is r(n)
        stalled = .false.
        if (n < 5) return
        stalled = minval(r(n - 3:n)) > 0.5_dp*r(n - 4)
        if (mod(n - 1, 4) == 0) stalled = stalled .or. r(n) > 0.5_dp*r(n - 4)
    end function newton_stalled

    !> Newton's correction ddu = A^-1 rhs on the free dofs (none prescribed), A the consistent
    !> tangents `tangents` assembled: by GMRES preconditioned with the factorisation the
    !> system holds (the last iteration's, or the midpoint corrector's) to a relative residual
    !> of krylov_rtol, else, when GMRES does not get there within krylov_iterations, by a
    !> numeric factorisation of A (docs/theory.md section 9, "Newton's corrections by
    !> GMRES"). The solves are without UMFPACK's iterative refinement, which the next Newton
    !> iteration does. Not with contact (its active set is decided on each solve).
    subroutine newton_correction(model, library, state, stress, tangents, rhs, residual, &
                                 first, system, ddu, result, context, error)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        real(dp), intent(in) :: stress(:, :, :), tangents(:, :, :, :), rhs(:, :)
        !> the relative residual of the iterate (the Newton loop's measure)
        real(dp), intent(in) :: residual
        !> the increment's first Newton iteration (the kept factorisation is not Newton's)
        logical, intent(in) :: first
        type(system_t), intent(inout) :: system
        real(dp), allocatable, intent(out) :: ddu(:, :)
        type(stage_result_t), intent(inout) :: result
        character(len=*), intent(in) :: context
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: b(:), x(:)
        real(dp) :: t0, rtol
        integer :: iterations
        logical :: converged
        t0 = wall_seconds()
        call assemble_tangent(model, library, state%active, system%pattern, stress, &
                              state%strain, state%history, system%values, tangents)
        result%stats%t_assembly = result%stats%t_assembly + (wall_seconds() - t0)
        allocate (b(system%pattern%n), x(system%pattern%n))
        associate (eq => system%dofmap%eq)
            b(pack(eq, eq > 0)) = pack(rhs, eq > 0)
        end associate
        call system%solver%set_refinement(.false.)
        ! Not in the first iteration, whose kept factorisation is the midpoint corrector's:
        ! measured, GMRES hardly ever reaches krylov_rtol with it (docs/performance.md (z)).
        converged = .false.
        iterations = 0
        t0 = wall_seconds()
        rtol = max(krylov_rtol, min(krylov_rtol_max, &
                                    krylov_share*model%tolerance/max(residual, tiny(1.0_dp))))
        if (.not. first .and. residual <= krylov_residual) &
            call gmres_solve(system%solver, system%pattern, system%values, b, x, rtol, &
                             krylov_iterations, converged, iterations, error)
        result%stats%t_solve = result%stats%t_solve + (wall_seconds() - t0)
        if (.not. (converged .or. allocated(error))) then
            ! UMFPACK's analysis of the consistent tangents' pattern with METIS (its first
            ! factorisation here makes it; docs/performance.md (z))
            call system%solver%set_metis(.true.)
            call factorise_values(system, result, context, error)
            system%factorised_linear = .false.
            if (.not. allocated(error)) then
                t0 = wall_seconds()
                call system%solver%solve(system%pattern, system%values, b, x, error)
                result%stats%t_solve = result%stats%t_solve + (wall_seconds() - t0)
            end if
        end if
        call system%solver%set_refinement(.true.)
        if (allocated(error)) then
            error%message = context//': '//error%message
            return
        end if
        if (all(ieee_is_finite(x))) then
            associate (eq => system%dofmap%eq)
                ddu = unpack(x(pack(eq, eq > 0)), eq > 0, 0.0_dp)
            end associate
        else
            call fatal_error(error, context//': the Newton correction is not finite', &
                             numerical_error)
        end if
    end subroutine newton_correction

    !> du = du_p + K^-1 (f_target - f_int(stress + D B du_p)) on the free dofs: the prescribed
    !> increment du_p moves the fixed dofs, and the forces it causes (K_fp du_p, through the
    !> tangent at `stress`) join the out-of-balance force. With contact the multipliers are
    !> solved with du and the active set iterated (cfrd_active_set); `du_base` is the
    !> increment already taken (Newton).
    subroutine solve_out_of_balance(model, library, state, stress, f_target, du_p, system, &
                                    du, result, context, error, contact, du_base, unsettled)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        real(dp), intent(in) :: stress(:, :, :), f_target(:, :), du_p(:, :)
        type(system_t), intent(inout) :: system
        real(dp), allocatable, intent(out) :: du(:, :)
        type(stage_result_t), intent(inout) :: result
        character(len=*), intent(in) :: context
        type(error_t), allocatable, intent(out) :: error
        type(contact_t), intent(inout), optional :: contact
        real(dp), intent(in), optional :: du_base(:, :)
        !> the error is the contact active set's failure to converge (solve_system)
        logical, intent(out), optional :: unsettled
        real(dp), allocatable :: f_int(:, :)
        allocate (f_int(2, model%mesh%nnode))
        if (any(du_p /= 0.0_dp)) then
            call internal_forces(model, library, state%active, &
                                 stress_after(model, library, state, stress, du_p), f_int)
        else
            call remembered_forces(model, library, state%active, stress, f_int, system%forces)
        end if
        call solve_system(model, f_target - f_int, du_p, system, du, result, context, error, &
                          contact, du_base, unsettled)
    end subroutine solve_out_of_balance

    !> Strain (or relative displacement) increments of element e for the nodal increment du,
    !> zero-padded to (4, ngauss); ng: the element's integration points.
    subroutine element_strains(model, library, e, du, strain, ng)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        integer, intent(in) :: e
        real(dp), intent(in) :: du(:, :)
        real(dp), intent(out) :: strain(4, ngauss)
        integer, intent(out) :: ng
        integer :: nn, nc
        associate (box => library(model%mesh%kind(e)), &
                   element => library(model%mesh%kind(e))%element)
            nn = element%nodes()
            ng = element%gauss_points()
            nc = element%components()
            strain = 0.0_dp
            call element%strains(box%geometry(box%slot(e)), gather(model, e, nn, du), &
                                 strain(1:nc, 1:ng))
        end associate
    end subroutine element_strains

    !> Stresses after the displacement increment du from `stress` (the state's stresses
    !> when absent): each point's law integrates its strain increment, with the tangent at
    !> the midpoint when `midpoint` (docs/theory.md sections 9 and 12). `stress_mid`
    !> returns the half-way stresses of that integration.
    subroutine integrate_stress(model, library, state, du, stress_end, stress_mid, midpoint, &
                                stress, creep_share, d_start, substeps)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        real(dp), intent(in) :: du(:, :)
        real(dp), allocatable, intent(out) :: stress_end(:, :, :), stress_mid(:, :, :)
        logical, intent(in) :: midpoint
        real(dp), intent(in), optional :: stress(:, :, :)
        !> the share of the increment's creep in du (1 for the whole increment, 0.5 for its
        !> half): the stresses the creep relaxes, D d_eps_c with the tangent at the start of
        !> the increment, come off the law's update over du (the initial-strain method with
        !> the load of the increment's solve, cfrd_creep_step)
        real(dp), intent(in), optional :: creep_share
        !> (4, 4, ngauss, nelem) the tangents at the start stresses, when the caller has
        !> them (start_tangents)
        real(dp), intent(in), optional :: d_start(:, :, :, :)
        !> (ngauss, nelem) sub-steps of each point's update (Newton: substep_counts)
        integer, intent(in), optional :: substeps(:, :)
        real(dp) :: strain(4, ngauss), start(4)
        integer :: e, ng, ig
        logical :: creeping
        if (present(stress)) then
            stress_end = stress
        else
            stress_end = state%stress
        end if
        stress_mid = stress_end
        ! Each element's points on one OpenMP thread: no sums across elements (the same
        ! bits for any thread count).
        !$omp parallel do schedule(dynamic, 32) private(strain, ng, ig, start, creeping) &
        !$omp if (model%mesh%nelem >= min_parallel)
        do e = 1, model%mesh%nelem
            if (.not. state%active(e)) cycle
            call element_strains(model, library, e, du, strain, ng)
            ! With creep, half the relaxed stresses come off before the law's update and
            ! half after: its midpoint tangent sits half-way along the stress path.
            creeping = .false.
            if (present(creep_share) .and. allocated(state%creep_stress)) creeping = .true.
            do ig = 1, ng
                start = stress_end(:, ig, e)
                if (creeping) start = start - 0.5_dp*creep_share*state%creep_stress(:, ig, e)
                if (present(substeps)) then
                    call material_update(model%materials(model%mesh%material(e)), model%pa, &
                                         start, state%strain(:, ig, e), &
                                         state%history(:, ig, e), strain(:, ig), midpoint, &
                                         stress_end(:, ig, e), stress_mid(:, ig, e), &
                                         d_start(:, :, ig, e), substeps(ig, e))
                else if (present(d_start)) then
                    call material_update(model%materials(model%mesh%material(e)), model%pa, &
                                         start, state%strain(:, ig, e), &
                                         state%history(:, ig, e), strain(:, ig), midpoint, &
                                         stress_end(:, ig, e), stress_mid(:, ig, e), &
                                         d_start(:, :, ig, e))
                else
                    call material_update(model%materials(model%mesh%material(e)), model%pa, &
                                         start, state%strain(:, ig, e), &
                                         state%history(:, ig, e), strain(:, ig), midpoint, &
                                         stress_end(:, ig, e), stress_mid(:, ig, e))
                end if
                if (creeping) stress_end(:, ig, e) = stress_end(:, ig, e) - &
                                                     0.5_dp*creep_share* &
                                                     state%creep_stress(:, ig, e)
            end do
        end do
        !$omp end parallel do
    end subroutine integrate_stress

    !> stress + D(stress) B du (forward Euler) at every point of the active elements.
    function stress_after(model, library, state, stress, du) result(stress_new)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        real(dp), intent(in) :: stress(:, :, :), du(:, :)
        real(dp), allocatable :: stress_new(:, :, :), stress_mid(:, :, :)
        call integrate_stress(model, library, state, du, stress_new, stress_mid, .false., &
                              stress)
    end function stress_after

    !> The tangent D at the start stress of every point of the active elements, as the
    !> Newton iterations' stress updates use it (integrate_stress with creep_share = 1: with
    !> creep, the start stress less half the increment's relaxed stresses).
    function start_tangents(model, library, state) result(d)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        real(dp), allocatable :: d(:, :, :, :)
        integer :: e, ig
        allocate (d(4, 4, ngauss, model%mesh%nelem), source=0.0_dp)
        !$omp parallel do schedule(dynamic, 32) private(ig) &
        !$omp if (model%mesh%nelem >= min_parallel)
        do e = 1, model%mesh%nelem
            if (.not. state%active(e)) cycle
            do ig = 1, library(model%mesh%kind(e))%element%gauss_points()
                call material_tangent(model%materials(model%mesh%material(e)), model%pa, &
                                      start_stress(state, ig, e), state%strain(:, ig, e), &
                                      state%history(:, ig, e), d(:, :, ig, e))
            end do
        end do
        !$omp end parallel do
    end function start_tangents

    !> The start stress of point ig of element e in the Newton iterations' stress updates.
    pure function start_stress(state, ig, e) result(start)
        type(state_t), intent(in) :: state
        integer, intent(in) :: ig, e
        real(dp) :: start(4)
        start = state%stress(:, ig, e)
        if (allocated(state%creep_stress)) start = start - 0.5_dp*state%creep_stress(:, ig, e)
    end function start_stress

    !> d sigma_end / d(delta eps) of the stress update at every point of the active elements
    !> (cfrd_material_law: material_update_tangent), Newton's tangent, from the start
    !> stresses and their tangents d_start (start_tangents). With `stress_end` and
    !> `stress_mid`: the update over du itself too (integrate_stress with midpoint,
    !> creep_share 1, d_start and substeps), in the same pass over the points
    !> (material_update_with_tangent): the line search's full step, whose tangent is the next
    !> iteration's when the step is taken.
    subroutine consistent_tangents(model, library, state, du, d_start, substeps, c, &
                                   stress_end, stress_mid)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        real(dp), intent(in) :: du(:, :), d_start(:, :, :, :)
        integer, intent(in) :: substeps(:, :)
        real(dp), allocatable, intent(out) :: c(:, :, :, :)
        real(dp), allocatable, intent(out), optional :: stress_end(:, :, :), stress_mid(:, :, :)
        real(dp) :: strain(4, ngauss)
        integer :: e, ng, ig
        logical :: update
        update = present(stress_end) .and. present(stress_mid)
        if (update) then
            stress_end = state%stress
            stress_mid = stress_end
        end if
        allocate (c(4, 4, ngauss, model%mesh%nelem), source=0.0_dp)
        !$omp parallel do schedule(dynamic, 32) private(strain, ng, ig) &
        !$omp if (model%mesh%nelem >= min_parallel)
        do e = 1, model%mesh%nelem
            if (.not. state%active(e)) cycle
            call element_strains(model, library, e, du, strain, ng)
            do ig = 1, ng
                associate (mat => model%materials(model%mesh%material(e)))
                    if (.not. update) then
                        call material_update_tangent(mat, model%pa, start_stress(state, ig, e), &
                                                     state%strain(:, ig, e), &
                                                     state%history(:, ig, e), strain(:, ig), &
                                                     c(:, :, ig, e), d_start(:, :, ig, e), &
                                                     substeps(ig, e))
                        cycle
                    end if
                    call material_update_with_tangent(mat, model%pa, start_stress(state, ig, e), &
                                                      state%strain(:, ig, e), &
                                                      state%history(:, ig, e), strain(:, ig), &
                                                      d_start(:, :, ig, e), substeps(ig, e), &
                                                      stress_end(:, ig, e), &
                                                      stress_mid(:, ig, e), c(:, :, ig, e))
                end associate
                if (allocated(state%creep_stress)) stress_end(:, ig, e) = &
                    stress_end(:, ig, e) - 0.5_dp*state%creep_stress(:, ig, e)
            end do
        end do
        !$omp end parallel do
    end subroutine consistent_tangents

    !> The start tangents D(sigma) of the Newton iterations' stress updates, the same in
    !> every iteration, and the sub-steps of each point's update where one step would pass
    !> the limit point of the midpoint rule (docs/theory.md section 9, "Sub-steps"): the
    !> counts for twice the predictor's increment du, as the corrections often take a
    !> point's strain increment past the predictor's [choice].
    subroutine newton_start(model, library, state, du, d_start, substeps, d_known)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        real(dp), intent(in) :: du(:, :)
        real(dp), allocatable, intent(out) :: d_start(:, :, :, :)
        integer, allocatable, intent(out) :: substeps(:, :)
        !> start_tangents of this state already evaluated for the predictor (without creep)
        real(dp), allocatable, intent(in), optional :: d_known(:, :, :, :)
        if (present(d_known)) then
            if (allocated(d_known)) d_start = d_known
        end if
        if (.not. allocated(d_start)) d_start = start_tangents(model, library, state)
        substeps = substep_counts(model, library, state, 2.0_dp*du, d_start)
    end subroutine newton_start

    !> The sub-steps of each point's stress update over du under Newton
    !> (cfrd_material_law: update_substeps), at least `floor` (the counts the increment's
    !> iterations have used so far: they only grow, so that the update stays one smooth
    !> function of du once they settle).
    function substep_counts(model, library, state, du, d_start, floor) result(n)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        real(dp), intent(in) :: du(:, :), d_start(:, :, :, :)
        integer, intent(in), optional :: floor(:, :)
        integer, allocatable :: n(:, :)
        real(dp) :: strain(4, ngauss)
        integer :: e, ng, ig
        allocate (n(ngauss, model%mesh%nelem), source=1)
        if (present(floor)) n = floor
        !$omp parallel do schedule(dynamic, 32) private(strain, ng, ig) &
        !$omp if (model%mesh%nelem >= min_parallel)
        do e = 1, model%mesh%nelem
            if (.not. state%active(e)) cycle
            call element_strains(model, library, e, du, strain, ng)
            do ig = 1, ng
                n(ig, e) = max(n(ig, e), &
                               update_substeps(model%materials(model%mesh%material(e)), &
                                               model%pa, start_stress(state, ig, e), &
                                               state%history(:, ig, e), strain(:, ig), &
                                               d_start(:, :, ig, e)))
            end do
        end do
        !$omp end parallel do
    end function substep_counts

    !> |f_target - f_int(stress)| over the free dofs; `roundoff`, the residual that floating
    !> point cannot resolve: 64 eps |sum of the magnitudes of the terms| (the forces of the
    !> elements, the contact and the loads that meet at each free dof).
    function out_of_balance(model, library, active, stress, f_target, dofmap, contact, &
                            worst, roundoff, force) result(norm)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        real(dp), intent(in) :: stress(:, :, :), f_target(:, :)
        type(dof_map_t), intent(in) :: dofmap
        type(contact_t), intent(in), optional :: contact
        !> 'node N (fx, fy kN/m)': the node of the largest out-of-balance force
        character(len=:), allocatable, intent(out), optional :: worst
        real(dp), intent(out), optional :: roundoff
        !> (2, nnode) the elements' internal forces f_int(stress), without the contact's
        real(dp), allocatable, intent(out), optional :: force(:, :)
        real(dp) :: norm
        real(dp), allocatable :: f_int(:, :), f_contact(:, :), r(:, :), magnitude(:, :)
        integer :: node
        allocate (f_int(2, model%mesh%nnode))
        if (present(roundoff)) then
            allocate (magnitude(2, model%mesh%nnode))
            call internal_forces(model, library, active, stress, f_int, magnitude)
            magnitude = magnitude + abs(f_target)
        else
            call internal_forces(model, library, active, stress, f_int)
        end if
        if (present(force)) force = f_int
        if (present(contact)) then
            allocate (f_contact(2, model%mesh%nnode))
            call contact_forces(contact, f_contact)
            f_int = f_int - f_contact
            if (present(roundoff)) magnitude = magnitude + abs(f_contact)
        end if
        r = merge(f_target - f_int, 0.0_dp, dofmap%eq > 0)
        norm = norm2(r)
        if (present(roundoff)) &
            roundoff = 64.0_dp*epsilon(1.0_dp)*norm2(merge(magnitude, 0.0_dp, dofmap%eq > 0))
        if (present(worst)) then
            node = maxloc(norm2(r, dim=1), dim=1)
            worst = 'node '//to_text(node)//' ('//real_text(r(1, node))//', '// &
                    real_text(r(2, node))//' kN/m)'
        end if
    end function out_of_balance

    !> After an accepted increment du: total strains since placement, and the laws' history.
    subroutine accept_history(model, library, state, du)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(inout) :: state
        real(dp), intent(in) :: du(:, :)
        real(dp) :: strain(4, ngauss)
        integer :: e, ig, ng
        !$omp parallel do schedule(dynamic, 32) private(strain, ig, ng) &
        !$omp if (model%mesh%nelem >= min_parallel)
        do e = 1, model%mesh%nelem
            if (.not. state%active(e)) cycle
            call element_strains(model, library, e, du, strain, ng)
            state%strain(:, 1:ng, e) = state%strain(:, 1:ng, e) + strain(:, 1:ng)
            do ig = 1, ng
                call update_history(model%materials(model%mesh%material(e)), model%pa, &
                                    state%stress(:, ig, e), state%history(:, ig, e))
            end do
        end do
        !$omp end parallel do
    end subroutine accept_history

end module cfrd_increment
