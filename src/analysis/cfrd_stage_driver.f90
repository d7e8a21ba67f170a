!> The stage driver: construction and loading stages in order, each in increments solved by
!> the midpoint stiffness method (modified Euler), forward Euler or Newton iterations, with the
!> sparse pattern and UMFPACK's symbolic factorisation kept while the set of active elements
!> holds (docs/theory.md, section 9).
module cfrd_stage_driver
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_clock, only: wall_seconds
    use cfrd_strings, only: to_text, fixed_text, level_text
    use cfrd_model, only: model_t, stage_t, stage_fill, stage_load, stage_reset, stage_water, &
                          stage_wait, stage_wet, no_date, has_creep, has_wetting, &
                          newtop_zero, dry_level, fill_active
    use cfrd_results, only: results_t, stage_result_t
    use cfrd_principal, only: principal_stresses
    use cfrd_material_law, only: nhistory, stress_level
    use cfrd_assembly, only: element_box_t, make_elements, load_set_forces, fill_forces, &
                             active_nodes, force_memo_t, remembered_forces
    use cfrd_water, only: water_forces, lowest_wet_point
    use cfrd_pjoint_results, only: perimetric_joints
    use cfrd_interface, only: interface_stations, phase_openings, slab_stresses
    use cfrd_body_extremes, only: body_extremes
    use cfrd_contact, only: new_contact
    use cfrd_contact_constraints, only: contact_forces
    use cfrd_contact_results, only: record_contact
    use cfrd_creep_step, only: creep_strains, wetting_strains, ncreep
    use cfrd_signals, only: stop_signal, stop_error
    use cfrd_linear_system, only: system_t, new_system, expect_next, forget_ahead
    use cfrd_stage_state, only: state_t, ngauss
    use cfrd_increment, only: solve_increment
    use cfrd_error_control, only: halvings, unbalanced_warning, may_grow
    use cfrd_restart_carry, only: carry_of, restore_state
    implicit none
    private

    public :: run_analysis, progress_interface, stored_interface

    !> Called after each stage, e.g. to print a progress line.
    abstract interface
        subroutine progress_interface(number, total, stage)
            import :: stage_result_t
            integer, intent(in) :: number, total
            type(stage_result_t), intent(in) :: stage
        end subroutine progress_interface

        !> Gives stage `number` of a results file as stored: its fields, carry and
        !> figures (a restart, cfrd --restart). `light` (asked for the stages before the
        !> last stored one): only what a stage's summary and CSV rows need may be given
        !> (displacements, stresses, strains, the contact state, near_failure); the callee
        !> sets it false when it gives, and needs, everything.
        subroutine stored_interface(number, stage, light, error)
            import :: stage_result_t, error_t
            integer, intent(in) :: number
            type(stage_result_t), intent(out) :: stage
            logical, intent(inout) :: light
            type(error_t), allocatable, intent(out) :: error
        end subroutine stored_interface
    end interface

contains

    !> Run every stage of the model. With `last_only`, results%stages holds the last stage
    !> only (each stage is handed to `progress`, which may write it away), so that memory
    !> does not grow with the number of stages.
    !> A restart (`stored` and `from_stage` K given): stages 1 .. K are not solved but read
    !> back through `stored`, their results recorded again from the stored state and handed
    !> to `progress` as computed ones; stage K+1 starts from the state stage K stored.
    subroutine run_analysis(model, results, error, progress, last_only, stored, from_stage)
        type(model_t), intent(in) :: model
        type(results_t), intent(out) :: results
        type(error_t), allocatable, intent(out) :: error
        procedure(progress_interface), optional :: progress
        logical, intent(in), optional :: last_only
        procedure(stored_interface), optional :: stored
        integer, intent(in), optional :: from_stage
        type(element_box_t), allocatable :: library(:)
        type(state_t) :: state
        type(system_t) :: system
        real(dp) :: t_start
        integer :: s, k, restart
        logical :: keep_all

        t_start = wall_seconds()
        keep_all = .true.
        if (present(last_only)) keep_all = .not. last_only
        call make_elements(model, library, error)
        if (allocated(error)) return
        call initial_state(model, state)
        if (allocated(model%contact_pairs)) then
            state%has_contact = size(model%contact_pairs) > 0
            if (state%has_contact) call new_contact(model, state%contact)
        end if
        allocate (results%stages(merge(size(model%stages), 1, keep_all)))
        restart = 0
        if (present(stored) .and. present(from_stage)) restart = from_stage
        call forget_ahead()
        do s = 1, size(model%stages)
            k = merge(s, 1, keep_all)
            if (s <= restart) then
                call stored_stage(s, results%stages(k), error)
            else
                call run_stage(model, library, s, state, system, results%stages(k), error)
            end if
            if (allocated(error)) exit
            if (present(progress)) call progress(s, size(model%stages), results%stages(k))
        end do
        ! the system prepared ahead reads the library: done with before it goes
        call forget_ahead()
        if (allocated(error)) return
        results%wall_time = wall_seconds() - t_start
    contains
        !> Stage `number` as stored, its state the state reached; after the last stored
        !> stage, the linear system of its active set with the stored multiplier scale.
        subroutine stored_stage(number, result, error)
            integer, intent(in) :: number
            type(stage_result_t), intent(inout) :: result
            type(error_t), allocatable, intent(out) :: error
            logical :: light
            light = number < restart
            call stored(number, result, light, error)
            if (allocated(error)) return
            call restore_state(result, state)
            call record(model, library, state, result, system%forces, light)
            call stage_labels(model%stages(number), state, result)
            if (number < restart .or. number == size(model%stages)) return
            call new_system(model, library, state%active, system, error, state%contact, &
                            state%has_contact)
            if (allocated(error)) return
            system%contact_scale = result%carry%contact_scale
            system%scale_given = .true.
        end subroutine stored_stage
    end subroutine run_analysis

    !> The active set after the first FILL stage after stage s (unallocated: none follows).
    pure function next_fill(model, s, active) result(next)
        type(model_t), intent(in) :: model
        integer, intent(in) :: s
        logical, intent(in) :: active(:)
        logical, allocatable :: next(:)
        integer :: j
        do j = s + 1, size(model%stages)
            if (model%stages(j)%kind /= stage_fill) cycle
            next = fill_active(model%mesh, active, model%stages(j)%group)
            return
        end do
    end function next_fill

    !> A stage result's label, kind, date, reservoir level and day.
    subroutine stage_labels(stage, state, result)
        type(stage_t), intent(in) :: stage
        type(state_t), intent(in) :: state
        type(stage_result_t), intent(inout) :: result
        result%name = stage%label
        result%kind = stage%kind
        result%date = ''
        if (allocated(stage%date)) result%date = stage%date
        result%water_level = state%level
        result%day = state%day
    end subroutine stage_labels

    !> Elements of groups that some FILL stage places start inactive; all others are active
    !> from the start (the foundation, or every element of a deck without FILL stages).
    subroutine initial_state(model, state)
        type(model_t), intent(in) :: model
        type(state_t), intent(out) :: state
        logical, allocatable :: filled_group(:)
        integer :: s, e
        associate (mesh => model%mesh)
            allocate (filled_group(0:size(mesh%group_name)), source=.false.)
            do s = 1, size(model%stages)
                if (model%stages(s)%kind == stage_fill) &
                    filled_group(model%stages(s)%group) = .true.
            end do
            allocate (state%active(mesh%nelem))
            do e = 1, mesh%nelem
                state%active(e) = .not. filled_group(mesh%group(e))
            end do
            allocate (state%u(2, mesh%nnode), state%f_ext(2, mesh%nnode), source=0.0_dp)
            allocate (state%u_before_reset(2, mesh%nnode), source=0.0_dp)
            allocate (state%stress(4, ngauss, mesh%nelem), source=0.0_dp)
            allocate (state%strain(4, ngauss, mesh%nelem), source=0.0_dp)
            allocate (state%history(nhistory, ngauss, mesh%nelem), source=0.0_dp)
            if (has_creep(model)) &
                allocate (state%creep(ncreep, ngauss, mesh%nelem), source=0.0_dp)
            if (has_wetting(model)) then
                allocate (state%wet(ncreep, ngauss, mesh%nelem), source=0.0_dp)
                allocate (state%wetted(mesh%nelem), source=.false.)
            end if
            if (has_creep(model) .or. has_wetting(model)) &
                allocate (state%creep_stress(4, ngauss, mesh%nelem), source=0.0_dp)
        end associate
    end subroutine initial_state

    subroutine run_stage(model, library, s, state, system, result, error)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        integer, intent(in) :: s
        type(state_t), intent(inout) :: state
        type(system_t), intent(inout) :: system
        type(stage_result_t), intent(out) :: result
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: stage_force(:, :), f_start(:, :), du_prescribed(:, :), &
                                 water_before(:, :), water_after(:, :)
        logical, allocatable :: was_used(:), wetting(:)
        real(dp) :: t0, t1, levels(2), dt
        integer :: nodes_before
        logical :: dry, creeps

        t0 = wall_seconds()
        associate (stage => model%stages(s), mesh => model%mesh)
            allocate (stage_force(2, mesh%nnode), du_prescribed(2, mesh%nnode), source=0.0_dp)
            was_used = active_nodes(model, state%active)
            nodes_before = count(was_used)
            allocate (water_before(2, mesh%nnode), water_after(2, mesh%nnode))
            levels = state%level
            ! The stage spans the time from the last date reached to its own date; the
            ! rockfill creeps over it in the stage's increments (docs/theory.md section 15).
            dt = 0.0_dp
            if (stage%day /= no_date) then
                if (state%day /= no_date) dt = stage%day - state%day
                state%day = stage%day
            end if
            creeps = allocated(state%creep) .and. dt > 0.0_dp
            select case (stage%kind)
            case (stage_reset)
                ! Time that passes before the reset creeps first, under the loads as they are.
                if (creeps) then
                    call creep_only(error)
                    if (allocated(error)) return
                end if
                state%u_before_reset = state%u_before_reset + state%u
                state%u = 0.0_dp
            case (stage_fill)
                ! The water on the faces the new group wets or covers changes with it.
                call water_forces(model, library, state%active, state%level, water_before)
                state%active = fill_active(mesh, state%active, stage%group)
                call fill_forces(model, library, stage%group, stage_force)
                call water_forces(model, library, state%active, state%level, water_after)
                stage_force = stage_force + water_after - water_before
            case (stage_water)
                ! The reservoir moves from its level (the lowest wetted point when it is
                ! still empty) to the stage's level in equal steps of level.
                levels(1) = state%level
                if (levels(1) == dry_level) levels(1) = min(lowest_wet_point(model), &
                                                            stage%level)
                levels(2) = stage%level
                state%level = stage%level
            case (stage_wet)
                ! The active elements of WETTING materials below the level, not wetted
                ! before, collapse over the stage's increments (docs/theory.md s. 16).
                wetting = state%active .and. .not. state%wetted .and. &
                          model%materials(mesh%material)%wetting .and. &
                          centroid_y(model) < stage%level
                state%wetted = state%wetted .or. wetting
            case (stage_load)
                call load_set_forces(model, library, model%load_sets(stage%load_set), &
                                     state%active, stage_force)
                ! The BOUNDARY displacement values are reached over the first LOAD stage of
                ! the default load set (docs/cards.md, STAGES).
                if (stage%load_set == 1 .and. .not. state%prescribed_done) then
                    du_prescribed = merge(model%prescribed, 0.0_dp, model%fixed)/ &
                                    stage%increments
                    state%prescribed_done = .true.
                end if
            end select
            ! The next FILL stage's system is prepared while this stage is solved.
            call expect_next(next_fill(model, s, state%active))

            ! A WATER stage without wetted faces (EFFECTS WATER OFF) only moves the level.
            dry = .true.
            if (allocated(model%wet_faces)) dry = size(model%wet_faces) == 0
            if ((stage%kind == stage_water .and. dry) .or. &
                (stage%kind == stage_wait .and. .not. creeps) .or. &
                (stage%kind == stage_wet .and. .not. any_true(wetting))) then
                ! Nothing to solve but the creep of the time that passes (if any).
                if (creeps) then
                    call creep_only(error)
                    if (allocated(error)) return
                end if
            else if (stage%kind /= stage_reset) then
                if (stage%kind == stage_fill .or. .not. allocated(system%values)) then
                    t1 = wall_seconds()
                    call new_system(model, library, state%active, system, error, &
                                    state%contact, state%has_contact)
                    if (allocated(error)) return
                    result%stats%t_pattern = result%stats%t_pattern + (wall_seconds() - t1)
                    result%stats%patterns = result%stats%patterns + 1
                end if
                result%stats%neq = system%pattern%n
                result%stats%nnz = system%pattern%nnz
                f_start = state%f_ext
                if (stage%kind == stage_water) then
                    call water_forces(model, library, state%active, levels(1), water_before)
                    f_start = f_start - water_before
                end if
                call run_increments(model, library, state, system, f_start, stage_force, &
                                    du_prescribed*stage%increments, stage%increments, s, &
                                    stage%label, result, error, &
                                    merge(levels, [dry_level, dry_level], &
                                          stage%kind == stage_water), dt, wetting)
                if (allocated(error)) return
                ! New layer's own nodes: their displacement during placement is not counted
                ! (NEWTOP = 0, docs/theory.md section 9).
                if (stage%kind == stage_fill .and. model%newtop == newtop_zero) then
                    associate (used => active_nodes(model, state%active))
                        where (spread(used .and. .not. was_used, 1, 2)) state%u = 0.0_dp
                    end associate
                end if
            end if
            call record(model, library, state, result, system%forces)
            call stage_labels(stage, state, result)
            result%carry = carry_of(state, system%contact_scale)
            result%wall_time = wall_seconds() - t0
        end associate
    contains
        !> The creep of the stage's time span under the loads as they are, in the stage's
        !> increments (a RESET, a WATER stage with nothing to wet, a WAIT).
        subroutine creep_only(error)
            type(error_t), allocatable, intent(out) :: error
            real(dp), allocatable :: no_force(:, :)
            logical, allocatable :: no_wetting(:)
            if (.not. allocated(system%values)) then
                call new_system(model, library, state%active, system, error, &
                                state%contact, state%has_contact)
                if (allocated(error)) return
                result%stats%patterns = result%stats%patterns + 1
            end if
            allocate (no_force(2, model%mesh%nnode), source=0.0_dp)
            call run_increments(model, library, state, system, state%f_ext, no_force, &
                                no_force, model%stages(s)%increments, s, &
                                model%stages(s)%label, result, error, &
                                [dry_level, dry_level], dt, no_wetting)
        end subroutine creep_only
    end subroutine run_stage

    !> The stage's load in `n` equal increments. An increment whose Newton iterations or
    !> contact active set do not converge (solve_increment's `stalled`) is cut in half and
    !> retried, at most `max_cutbacks` times in a row; after a success the step grows back
    !> towards the nominal one. Cutbacks are counted in the stage's result. When `levels` is
    !> not dry the reservoir moves from levels(1) to levels(2) in the same steps, and its
    !> forces at the reached level join f_start.
    subroutine run_increments(model, library, state, system, f_start, stage_force, &
                              du_stage, n, s, label, result, error, levels, dt, wetting)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(inout) :: state
        type(system_t), intent(inout) :: system
        real(dp), intent(in) :: f_start(:, :), stage_force(:, :), du_stage(:, :)
        integer, intent(in) :: n, s
        character(len=*), intent(in) :: label
        type(stage_result_t), intent(inout) :: result
        type(error_t), allocatable, intent(out) :: error
        real(dp), intent(in) :: levels(2)
        !> days the stage spans: the rockfill creeps over each increment's share of it
        real(dp), intent(in) :: dt
        !> the elements that collapse on wetting in this stage (a WET stage)
        logical, allocatable, intent(in) :: wetting(:)
        integer, parameter :: max_cutbacks = 6, max_growth = 64
        real(dp), allocatable :: creep_before(:, :, :), wet_before(:, :, :)
        logical :: creeps, wets
        real(dp) :: done, step, nominal, level, residual
        logical :: unbalanced, rejectable, rejected, stalled
        real(dp), allocatable :: f_water(:, :)
        integer :: cuts, k
        character(len=:), allocatable :: context
        allocate (f_water(2, model%mesh%nnode), source=0.0_dp)
        nominal = 1.0_dp/n
        step = nominal
        done = 0.0_dp
        cuts = 0
        k = 0
        do while (done < 1.0_dp - 1.0e-12_dp)
            ! SIGINT / SIGTERM: stop before the next increment (cfrd_signals).
            if (stop_signal() /= 0) then
                call stop_error(error, 'in stage '//to_text(s)//' ('//label//')')
                return
            end if
            step = min(step, 1.0_dp - done)
            k = k + 1
            context = 'stage '//to_text(s)//' ('//label//'), increment '//to_text(k)// &
                      ' (load fraction '//fixed_text(done)//' to '//fixed_text(done + step)//')'
            if (levels(2) /= dry_level) then
                level = levels(1) + (levels(2) - levels(1))*(done + step)
                if (done + step >= 1.0_dp - 1.0e-12_dp) level = levels(2)
                call water_forces(model, library, state%active, level, f_water)
                context = context//', water level '//level_text(level)//' m'
            end if
            creeps = allocated(state%creep) .and. dt > 0.0_dp
            if (creeps) then
                creep_before = state%creep
                call creep_strains(model, library, state%active, dt*step, state%stress, &
                                   state%strain, state%history, state%creep, &
                                   state%creep_stress)
            end if
            wets = any_true(wetting)
            if (wets) then
                ! the increment's share of the collapse that remains (all of it at the end)
                wet_before = state%wet
                call wetting_strains(model, library, wetting, &
                                     min(1.0_dp, step/max(1.0_dp - done, step)), &
                                     state%stress, state%strain, state%history, state%wet, &
                                     state%creep_stress)
            end if
            ! Midpoint / Euler out of balance beyond ERRTOL: rejected, and redone in two
            ! halves, down to DEPTH halvings of the nominal increment (cfrd_error_control).
            rejectable = halvings(step, nominal) < model%max_depth
            call solve_increment(model, library, state, system, &
                                 f_start + f_water + stage_force*(done + step), &
                                 du_stage*step, result, context, error, residual, &
                                 rejectable, unbalanced, stalled)
            rejected = .not. allocated(error) .and. unbalanced .and. rejectable
            if (creeps .or. wets) then
                ! the step's creep and wetting are spent (or, not accepted, undone)
                if ((allocated(error) .or. rejected) .and. creeps) state%creep = creep_before
                if ((allocated(error) .or. rejected) .and. wets) state%wet = wet_before
                state%creep_stress = 0.0_dp
            end if
            if (rejected) then
                result%cutbacks = result%cutbacks + 1
                step = 0.5_dp*step
                k = k - 1
                cycle
            end if
            if (allocated(error)) then
                ! Only a convergence failure (Newton, the contact active set) is cut back.
                if (.not. stalled) return
                if (cuts == max_cutbacks) then
                    error%message = error%message//'; the increment cut back '// &
                                    to_text(cuts)//' times in a row (to '// &
                                    fixed_text(step/nominal)//' of its nominal size)'
                    return
                end if
                ! Cutbacks that keep succeeding once and failing again must not run on for
                ! ever: at most max_growth times the nominal increments per stage.
                if (k > max_growth*n) then
                    error%message = error%message//'; stopped after '//to_text(k)// &
                                    ' increments in this stage (more than '// &
                                    to_text(max_growth)//' times the '//to_text(n)// &
                                    ' asked for)'
                    return
                end if
                ! Nothing of the state changed: retry the increment in two halves.
                deallocate (error)
                cuts = cuts + 1
                result%cutbacks = result%cutbacks + 1
                step = 0.5_dp*step
                k = k - 1
                cycle
            end if
            ! At the depth limit an increment above ERRTOL is accepted with a warning.
            if (unbalanced) then
                result%unbalanced = result%unbalanced + 1
                if (.not. allocated(result%warning)) &
                    result%warning = unbalanced_warning(model, context, residual, &
                                                        halvings(step, nominal))
            end if
            done = done + step
            result%increments = result%increments + 1
            cuts = 0
            if (may_grow(model, residual)) step = min(2.0_dp*step, nominal)
        end do
    end subroutine run_increments

    !> The stage's results: displacements, stresses, principal stresses, reactions.
    !> `light`: a stored stage's summary and CSV rows only (stress levels, reactions and the
    !> Gauss-point fields are left out).
    subroutine record(model, library, state, result, forces, light)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        type(stage_result_t), intent(inout) :: result
        !> the internal forces of the last accepted stresses (the system's)
        type(force_memo_t), intent(inout) :: forces
        logical, intent(in), optional :: light
        real(dp), allocatable :: f_int(:, :)
        logical, allocatable :: used(:)
        integer :: e, ig, ng
        associate (mesh => model%mesh)
            result%active = state%active
            result%displacement = state%u
            result%displacement_total = state%u_before_reset + state%u
            if (allocated(model%interfaces)) then
                call interface_stations(model, state%stress, state%strain, state%active, &
                                        result%interface)
                call phase_openings(model, result%interface, result%openings)
                call perimetric_joints(model, result%interface, result%pjoint)
            end if
            if (allocated(model%slab_groups)) &
                call slab_stresses(model, state%stress, state%active, result%slab)
            if (state%has_contact) call record_contact(model, state%contact, state%active, &
                                                       result%contact, result%openings)
            allocate (result%stress_centroid(4, mesh%nelem), result%principal(3, mesh%nelem))
            do e = 1, mesh%nelem
                ng = library(mesh%kind(e))%element%gauss_points()
                result%stress_centroid(:, e) = sum(state%stress(:, 1:ng, e), dim=2)/ng
                result%principal(:, e) = 0.0_dp
                ! Principal stresses of solids; a joint's (sigma_n, tau) have none.
                if (library(mesh%kind(e))%element%components() == 4) &
                    result%principal(:, e) = principal_stresses(result%stress_centroid(:, e))
            end do
            if (allocated(model%slab_groups)) then
                if (size(model%slab_groups) > 0) then
                    used = [(library(mesh%kind(e))%element%components() == 4, e=1, mesh%nelem)]
                    if (allocated(model%interfaces)) used(model%interfaces%element) = .false.
                    call body_extremes(model, result%principal, state%active, used, &
                                       result%slab, result%extremes, result%singular_nodes, &
                                       result%singular_radius, result%singular_why)
                end if
            end if
            if (present(light)) then
                if (light) return
            end if
            allocate (result%stress_level(mesh%nelem), source=0.0_dp)
            do e = 1, mesh%nelem
                if (.not. state%active(e)) cycle
                do ig = 1, library(mesh%kind(e))%element%gauss_points()
                    result%stress_level(e) = max(result%stress_level(e), stress_level( &
                        model%materials(mesh%material(e)), model%pa, state%stress(:, ig, e)))
                end do
            end do
            ! Near failure: stress level 0.95 or more (the law caps it at 0.99).
            result%near_failure = count(result%stress_level >= 0.95_dp)
            result%stress_gauss = state%stress
            result%strain_gauss = state%strain
            result%history_gauss = state%history
            if (allocated(state%creep)) result%creep_gauss = state%creep
            if (allocated(state%wet)) result%wetting_gauss = state%wet
            allocate (f_int(2, mesh%nnode))
            call remembered_forces(model, library, state%active, state%stress, f_int, forces)
            if (state%has_contact) then
                ! contact forces are internal to the model: reactions see their sum
                block
                    real(dp), allocatable :: f_contact(:, :)
                    allocate (f_contact(2, mesh%nnode))
                    call contact_forces(state%contact, f_contact)
                    f_int = f_int - f_contact
                end block
            end if
            used = active_nodes(model, state%active)
            result%reaction = merge(f_int - state%f_ext, 0.0_dp, &
                                    model%fixed .and. spread(used, 1, 2))
            result%applied_load = sum(state%f_ext, dim=2)
            result%reaction_sum = sum(result%reaction, dim=2)
        end associate
    end subroutine record

    !> Whether an optional mask is given and holds some true entry.
    pure logical function any_true(mask)
        logical, allocatable, intent(in) :: mask(:)
        any_true = .false.
        if (allocated(mask)) any_true = any(mask)
    end function any_true

    !> The elevation of each element's centroid (the mean of its corner nodes).
    pure function centroid_y(model) result(y)
        type(model_t), intent(in) :: model
        real(dp), allocatable :: y(:)
        integer :: e, nn
        allocate (y(model%mesh%nelem))
        do e = 1, model%mesh%nelem
            associate (conn => model%mesh%conn(:, e))
                nn = size(conn)
                if (conn(nn) == conn(nn - 1)) nn = nn - 1   ! a triangle (degenerate quad)
                y(e) = sum(model%mesh%x(2, conn(1:nn)))/nn
            end associate
        end do
    end function centroid_y

end module cfrd_stage_driver
