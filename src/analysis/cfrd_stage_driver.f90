!> The stage driver: construction and loading stages in order, each in increments solved by
!> the midpoint stiffness method (modified Euler), forward Euler or Newton iterations, with the
!> sparse pattern and UMFPACK's symbolic factorisation kept while the set of active elements
!> holds (docs/theory.md, section 9).
module cfrd_stage_driver
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, numerical_error
    use cfrd_clock, only: wall_seconds
    use cfrd_strings, only: to_text, real_text, fixed_text, level_text
    use cfrd_model, only: model_t, stage_fill, stage_load, stage_reset, stage_water, &
                          stage_wait, no_date, has_creep, &
                          newtop_zero, solver_euler, solver_newton, dry_level
    use cfrd_results, only: results_t, stage_result_t, solver_stats_t
    use cfrd_sparse, only: sparse_pattern_t, build_pattern
    use cfrd_umfpack, only: umfpack_t
    use cfrd_principal, only: principal_stresses
    use cfrd_material_law, only: nhistory, is_linear, update_history, stress_level, &
                                 material_update, material_update_tangent
    use cfrd_assembly, only: element_box_t, dof_map_t, make_elements, number_equations, &
                             load_set_forces, fill_forces, assemble_tangent, internal_forces, &
                             gather, active_nodes
    use cfrd_water, only: water_forces, lowest_wet_point
    use cfrd_interface, only: interface_stations, phase_openings, slab_stresses
    use cfrd_contact, only: contact_t, new_contact, contact_geometry, contact_element_dofs, &
                            contact_element_matrix, contact_rhs, contact_unpack, &
                            contact_update_sets, contact_forces, contact_accept, &
                            contact_iteration_limit, contact_slip, contact_stick, &
                            contact_stick_excess
    use cfrd_contact_results, only: record_contact
    use cfrd_creep_step, only: creep_strains, ncreep
    use cfrd_sparse, only: assemble_element
    use cfrd_signals, only: stop_signal, stop_error
    implicit none
    private

    public :: run_analysis, progress_interface

    !> Most integration points of any element kind (quads 4, joints 2).
    integer, parameter :: ngauss = 4

    !> Called after each stage, e.g. to print a progress line.
    abstract interface
        subroutine progress_interface(number, total, stage)
            import :: stage_result_t
            integer, intent(in) :: number, total
            type(stage_result_t), intent(in) :: stage
        end subroutine progress_interface
    end interface

    !> The evolving state: displacements since the last reset, Gauss-point stresses and
    !> history, active elements, the external load applied so far and the reservoir level.
    type :: state_t
        real(dp), allocatable :: u(:, :)             !! (2, nnode)
        real(dp), allocatable :: u_before_reset(:, :) !! (2, nnode) sum of u at the resets
        real(dp), allocatable :: stress(:, :, :)     !! (4, ngauss, nelem)
        !> (4, ngauss, nelem) total strain since placement (a joint: relative displacement)
        real(dp), allocatable :: strain(:, :, :)
        real(dp), allocatable :: history(:, :, :)    !! (nhistory, ngauss, nelem)
        logical, allocatable :: active(:)            !! (nelem)
        real(dp), allocatable :: f_ext(:, :)         !! (2, nnode) applied so far
        logical :: prescribed_done = .false.         !! BOUNDARY values applied
        real(dp) :: level = dry_level                !! reservoir level, m
        !> (ncreep, ngauss, nelem) creep strains reached (only when some material creeps)
        real(dp), allocatable :: creep(:, :, :)
        !> (4, ngauss, nelem) D times the creep strain of the increment being solved (the load
        !> it puts on the increment); zero outside creeping increments
        real(dp), allocatable :: creep_stress(:, :, :)
        real(dp) :: day = no_date                    !! the date reached, day number
        logical :: has_contact = .false.             !! the deck has CONTACT pairs
        type(contact_t) :: contact                   !! their state (docs/theory.md s. 14)
    end type state_t

    !> The linear-algebra objects of one active set.
    type :: system_t
        type(dof_map_t) :: dofmap
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:)
        logical :: factorised_linear = .false.   !! a constant tangent is factorised already
        logical :: analysed = .false.            !! the symbolic factorisation exists
        !> With contact: the tangent K alone (the contact rows are added per active set),
        !> and the scale of the multipliers (a stiffness per length, docs/theory.md s. 14)
        real(dp), allocatable :: k_values(:)
        real(dp) :: contact_scale = 1.0_dp
        !> (2, ncontact) the normal / tangential constraint of a slave node moves some free
        !> dof (else every dof it ties is prescribed: the constraint is left out)
        logical, allocatable :: constrains(:, :)
        !> Regularisation of the slip rows for this solve (contact_element_matrix): 0, or
        !> slip_viscosity after a singular factorisation with sliding nodes
        real(dp) :: viscous = 0.0_dp
    end type system_t

    !> The slip rows' regularisation when a body held by friction alone slips at every
    !> node (a mechanism of the linearised equations): q = mu p sign - 1e-9 c_n slip.
    real(dp), parameter :: slip_viscosity = 1.0e-9_dp
    !> A slave node whose status changes this often in one solve chatters: it is held in
    !> stick (docs/theory.md section 14).
    integer, parameter :: chatter_flips = 4
    !> ... once the iteration has run this long without settling (half the limit): the
    !> chatter of converging iterations is left alone.
    integer, parameter :: chatter_start = contact_iteration_limit/2
    !> Held nodes are accepted when no one's excess over its stick conditions (tension, or
    !> shear beyond mu p) exceeds this fraction of the largest contact pressure.
    real(dp), parameter :: held_tolerance = 1.0e-3_dp

contains

    !> Run every stage of the model. With `last_only`, results%stages holds the last stage
    !> only (each stage is handed to `progress`, which may write it away), so that memory
    !> does not grow with the number of stages.
    subroutine run_analysis(model, results, error, progress, last_only)
        type(model_t), intent(in) :: model
        type(results_t), intent(out) :: results
        type(error_t), allocatable, intent(out) :: error
        procedure(progress_interface), optional :: progress
        logical, intent(in), optional :: last_only
        type(element_box_t), allocatable :: library(:)
        type(state_t) :: state
        type(system_t) :: system
        real(dp) :: t_start
        integer :: s, k
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
        do s = 1, size(model%stages)
            k = merge(s, 1, keep_all)
            call run_stage(model, library, s, state, system, results%stages(k), error)
            if (allocated(error)) return
            if (present(progress)) call progress(s, size(model%stages), results%stages(k))
        end do
        results%wall_time = wall_seconds() - t_start
    end subroutine run_analysis

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
            if (has_creep(model)) then
                allocate (state%creep(ncreep, ngauss, mesh%nelem), source=0.0_dp)
                allocate (state%creep_stress(4, ngauss, mesh%nelem), source=0.0_dp)
            end if
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
        logical, allocatable :: was_used(:)
        real(dp) :: t0, t1, levels(2), dt
        integer :: nodes_before
        logical :: dry, creeps

        t0 = wall_seconds()
        associate (stage => model%stages(s), mesh => model%mesh)
            result%name = stage%label
            result%kind = stage%kind
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
                where (mesh%group == stage%group) state%active = .true.
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

            ! A WATER stage without wetted faces (EFFECTS WATER OFF) only moves the level.
            dry = .true.
            if (allocated(model%wet_faces)) dry = size(model%wet_faces) == 0
            if ((stage%kind == stage_water .and. dry) .or. &
                (stage%kind == stage_wait .and. .not. creeps)) then
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
                                          stage%kind == stage_water), dt)
                if (allocated(error)) return
                ! New layer's own nodes: their displacement during placement is not counted
                ! (NEWTOP = 0, docs/theory.md section 9).
                if (stage%kind == stage_fill .and. model%newtop == newtop_zero) then
                    associate (used => active_nodes(model, state%active))
                        where (spread(used .and. .not. was_used, 1, 2)) state%u = 0.0_dp
                    end associate
                end if
            end if
            call record(model, library, state, result)
            result%date = ''
            if (allocated(stage%date)) result%date = stage%date
            result%water_level = state%level
            result%day = state%day
            result%wall_time = wall_seconds() - t0
        end associate
    contains
        !> The creep of the stage's time span under the loads as they are, in the stage's
        !> increments (a RESET, a WATER stage with nothing to wet, a WAIT).
        subroutine creep_only(error)
            type(error_t), allocatable, intent(out) :: error
            real(dp), allocatable :: no_force(:, :)
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
                                [dry_level, dry_level], dt)
        end subroutine creep_only
    end subroutine run_stage

    !> The stage's load in `n` equal increments. An increment whose Newton iterations do not
    !> converge is cut in half and retried, at most `max_cutbacks` times in a row; after a
    !> success the step grows back towards the nominal one. Cutbacks are counted in the
    !> stage's result. When `levels` is not dry the reservoir moves from levels(1) to
    !> levels(2) in the same steps, and its forces at the reached level join f_start.
    subroutine run_increments(model, library, state, system, f_start, stage_force, &
                              du_stage, n, s, label, result, error, levels, dt)
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
        integer, parameter :: max_cutbacks = 6, max_growth = 64
        real(dp), allocatable :: creep_before(:, :, :)
        logical :: creeps
        real(dp) :: done, step, nominal, level
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
            call solve_increment(model, library, state, system, &
                                 f_start + f_water + stage_force*(done + step), &
                                 du_stage*step, result, context, error)
            if (creeps) then
                ! the step's creep is spent (or, after no convergence, undone)
                if (allocated(error)) state%creep = creep_before
                state%creep_stress = 0.0_dp
            end if
            if (allocated(error)) then
                if (index(error%message, 'no convergence') == 0) return
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
            done = done + step
            result%increments = result%increments + 1
            cuts = 0
            step = min(2.0_dp*step, nominal)
        end do
    end subroutine run_increments



    !> Equations, pattern and a fresh solver for the current active set.
    !> With contact, each slave node is one more element (its coupled nodes and its two
    !> multiplier equations, numbered after the displacement equations).
    subroutine new_system(model, library, active, system, error, contact, has_contact)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        type(system_t), intent(inout) :: system
        type(error_t), allocatable, intent(out) :: error
        type(contact_t), intent(in) :: contact
        logical, intent(in) :: has_contact
        integer, allocatable :: dof_ptr(:), dofs(:), more(:)
        integer :: c, nelem, pos
        call system%solver%release()
        call number_equations(model, library, active, system%dofmap)
        if (has_contact) then
            nelem = model%mesh%nelem
            allocate (dof_ptr(nelem + contact%nc + 1))
            dof_ptr(1:nelem + 1) = system%dofmap%dof_ptr
            do c = 1, contact%nc
                dof_ptr(nelem + c + 1) = dof_ptr(nelem + c) + 2* &
                    (contact%cpl_ptr(c + 1) - contact%cpl_ptr(c)) + 2
            end do
            allocate (dofs(dof_ptr(nelem + contact%nc + 1) - 1))
            dofs(1:size(system%dofmap%dofs)) = system%dofmap%dofs
            pos = dof_ptr(nelem + 1)
            do c = 1, contact%nc
                more = contact_element_dofs(contact, c, system%dofmap%eq, system%dofmap%neq)
                dofs(pos:pos + size(more) - 1) = more
                pos = pos + size(more)
            end do
            call build_pattern(system%pattern, system%dofmap%neq + 2*contact%nc, dof_ptr, &
                               dofs, error)
            system%constrains = constraining_rows(contact, system%dofmap%eq)
            ! The multipliers are scaled to K's size (multiplier_scale): UMFPACK's row
            ! scaling would only push its pivots off the diagonal.
            call system%solver%set_row_scaling(.false.)
        else
            call build_pattern(system%pattern, system%dofmap%neq, system%dofmap%dof_ptr, &
                               system%dofmap%dofs, error)
        end if
        if (allocated(error)) return
        if (allocated(system%k_values)) deallocate (system%k_values)
        if (allocated(system%values)) deallocate (system%values)
        allocate (system%values(system%pattern%nnz), source=0.0_dp)
        system%factorised_linear = .false.
        system%analysed = .false.
    end subroutine new_system

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
                if (.not. allocated(system%k_values)) system%contact_scale = &
                    multiplier_scale(system, contact)
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

    !> The multiplier scale: the largest diagonal entry of K over the largest slave node
    !> length, so that the contact entries (scale x length) are of the size of K's.
    pure real(dp) function multiplier_scale(system, contact) result(scale)
        type(system_t), intent(in) :: system
        type(contact_t), intent(in) :: contact
        real(dp) :: diagonal
        integer :: j, p
        diagonal = 0.0_dp
        do j = 1, system%dofmap%neq
            do p = system%pattern%colptr(j) + 1, system%pattern%colptr(j + 1)
                if (system%pattern%rowind(p) == j - 1) &
                    diagonal = max(diagonal, abs(system%values(p)))
            end do
        end do
        scale = max(diagonal, tiny(1.0_dp))
        if (maxval([0.0_dp, contact%wref]) > 0.0_dp) scale = scale/maxval(contact%wref)
    end function multiplier_scale

    !> Whether each slave node's normal and tangential constraints act on the free dofs:
    !> the rows restricted to the free dofs are not (nearly) zero, and the tangential row is
    !> not (nearly) parallel to the normal one (a node on a symmetry line with ux prescribed:
    !> its slip is the supports' business). A constraint that does not is left out.
    pure function constraining_rows(contact, eq) result(constrains)
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: eq(:, :)
        logical, allocatable :: constrains(:, :)
        real(dp), allocatable :: rn(:), rt(:)
        real(dp) :: total, nn, tt
        integer :: c, k, node, m
        allocate (constrains(2, contact%nc))
        do c = 1, contact%nc
            m = contact%cpl_ptr(c + 1) - contact%cpl_ptr(c)
            allocate (rn(2*m), rt(2*m))
            total = 0.0_dp
            do k = 1, m
                node = contact%cpl_node(contact%cpl_ptr(c) + k - 1)
                total = total + abs(contact%cpl_a(contact%cpl_ptr(c) + k - 1))
                rn(2*k - 1:2*k) = merge(contact%cpl_a(contact%cpl_ptr(c) + k - 1)* &
                                        contact%normal(:, c), 0.0_dp, eq(:, node) > 0)
                rt(2*k - 1:2*k) = merge(contact%cpl_a(contact%cpl_ptr(c) + k - 1)* &
                                        contact%tangent(:, c), 0.0_dp, eq(:, node) > 0)
            end do
            ! relative 1e-9: a dual multiplier's weight on a linear field's values away from
            ! its node is zero up to round-off
            nn = dot_product(rn, rn)
            tt = dot_product(rt, rt)
            constrains(1, c) = sqrt(nn) > 1.0e-9_dp*total
            constrains(2, c) = sqrt(tt) > 1.0e-9_dp*total
            if (constrains(1, c) .and. constrains(2, c)) &
                constrains(2, c) = nn*tt - dot_product(rn, rt)**2 > 1.0e-9_dp*nn*tt
            deallocate (rn, rt)
        end do
    end function constraining_rows

    !> K plus the contact rows of the current active set, factorised. With `update`, K is the
    !> one factorised last and only contact rows changed: when few did, the factorisation is
    !> updated for them (umfpack_t%update_rows, a few solves) instead of being redone.
    subroutine factorise_contact(model, system, contact, result, context, error, update)
        type(model_t), intent(in) :: model
        type(system_t), intent(inout) :: system
        type(contact_t), intent(in) :: contact
        type(stage_result_t), intent(inout) :: result
        character(len=*), intent(in) :: context
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in) :: update
        real(dp), allocatable :: ke(:, :)
        real(dp) :: t0
        logical :: done
        integer :: c, m, attempt
        do attempt = 1, 2
            t0 = wall_seconds()
            system%values = system%k_values
            do c = 1, contact%nc
                m = 2*(contact%cpl_ptr(c + 1) - contact%cpl_ptr(c)) + 2
                allocate (ke(m, m))
                call contact_element_matrix(contact, c, &
                                            model%contact_pairs(contact%pair(c))%friction, &
                                            system%contact_scale, system%constrains(:, c), ke, &
                                            system%viscous)
                call assemble_element(system%pattern, system%values, model%mesh%nelem + c, ke)
                deallocate (ke)
            end do
            result%stats%t_assembly = result%stats%t_assembly + (wall_seconds() - t0)
            if (update .and. attempt == 1) then
                t0 = wall_seconds()
                call system%solver%update_rows(system%pattern, system%values, done, error)
                if (allocated(error)) then
                    error%message = context//': '//error%message
                    return
                end if
                result%stats%t_update = result%stats%t_update + (wall_seconds() - t0)
                if (done) then
                    result%stats%updates = result%stats%updates + 1
                    return
                end if
            end if
            call factorise_values(system, result, context, error)
            if (.not. allocated(error)) return
            if (system%viscous > 0.0_dp .or. attempt == 2 .or. &
                .not. any(contact%status == contact_slip)) call mechanism_hint()
            ! Sliding everywhere, a body held by friction alone is a mechanism of the
            ! linearised equations: regularise the slip rows and try once more.
            if (system%viscous > 0.0_dp .or. .not. any(contact%status == contact_slip) .or. &
                index(error%message, 'singular') == 0) return
            system%viscous = slip_viscosity
            result%stats%regularised = result%stats%regularised + 1
            deallocate (error)
        end do
    contains
        !> A singular matrix with frictionless sliding nodes: name them (a body held by
        !> frictionless contact alone is a mechanism, docs/cards.md CONTACT).
        subroutine mechanism_hint()
            logical, allocatable :: sliding(:)
            sliding = contact%status /= contact_stick .and. contact%placed
            do c = 1, contact%nc
                if (model%contact_pairs(contact%pair(c))%friction > 0.0_dp) sliding(c) = .false.
            end do
            if (.not. any(sliding)) return
            error%message = error%message//'; '//to_text(count(sliding))//' slave nodes '// &
                'of frictionless pairs (MU = 0) slide or are open, the first node '// &
                to_text(contact%node(findloc(sliding, .true., dim=1)))// &
                trim(merge(' (slip rows regularised)', '                        ', &
                           system%viscous > 0.0_dp))//': a body held by frictionless contact '// &
                'alone is a mechanism (hold it by BOUNDARY cards or give the pair friction)'
        end subroutine mechanism_hint
    end subroutine factorise_contact

    !> Factorise system%values (the symbolic phase once per pattern).
    subroutine factorise_values(system, result, context, error)
        type(system_t), intent(inout) :: system
        type(stage_result_t), intent(inout) :: result
        character(len=*), intent(in) :: context
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: t1
        t1 = wall_seconds()
        if (.not. system%analysed) then
            ! Symbolic factorisation once per pattern (after the first assembly, so that
            ! UMFPACK sees the values it orders for).
            call system%solver%analyse(system%pattern, system%values, error)
            if (allocated(error)) then
                error%message = context//': '//error%message
                return
            end if
            system%analysed = .true.
            result%stats%t_symbolic = result%stats%t_symbolic + (wall_seconds() - t1)
            result%stats%analyses = result%stats%analyses + 1
            t1 = wall_seconds()
        end if
        call system%solver%factorise(system%pattern, system%values, error)
        if (allocated(error)) then
            error%message = context//': '//error%message
            return
        end if
        result%stats%t_numeric = result%stats%t_numeric + (wall_seconds() - t1)
        result%stats%rcond = system%solver%rcond()
        result%stats%lu_nnz = system%solver%factor_nonzeros()
        result%factorisations = result%factorisations + 1
    end subroutine factorise_values

    pure logical function all_linear(model, active)
        type(model_t), intent(in) :: model
        logical, intent(in) :: active(:)
        integer :: e
        all_linear = .true.
        do e = 1, model%mesh%nelem
            if (.not. active(e)) cycle
            if (.not. is_linear(model%materials(model%mesh%material(e)))) then
                all_linear = .false.
                return
            end if
        end do
    end function all_linear

    !> One increment to the external load `f_target`: the right-hand side is the out-of-
    !> balance force f_target - f_int(sigma_n), so that the residual left by earlier increments
    !> is carried into this one (equilibrium correction). With contact, the geometry is
    !> updated first (the paper's Step 6) and each solve iterates the active set; the contact
    !> state changes only when the increment is accepted.
    subroutine solve_increment(model, library, state, system, f_target, du_prescribed, &
                               result, context, error)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(inout) :: state
        type(system_t), intent(inout) :: system
        real(dp), intent(in) :: f_target(:, :)
        real(dp), intent(in) :: du_prescribed(:, :)   !! increment of prescribed displacements
        type(stage_result_t), intent(inout) :: result
        character(len=*), intent(in) :: context
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: du(:, :), stress_end(:, :, :), stress_mid(:, :, :)
        real(dp) :: residual, load_norm, recent, t0
        real(dp), allocatable :: rhs_stress(:, :, :)
        integer :: iteration
        type(contact_t), allocatable :: contact
        logical :: changed, searched

        load_norm = max(norm2(f_target), tiny(1.0_dp))
        system%viscous = 0.0_dp
        if (state%has_contact) then
            contact = state%contact
            t0 = wall_seconds()
            call contact_geometry(model, state%active, contact, changed, searched)
            result%stats%t_contact = result%stats%t_contact + (wall_seconds() - t0)
            if (searched) result%stats%searches = result%stats%searches + 1
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
        ! Predictor with the tangent at the start of the increment.
        call factorise_at(model, library, state, state%stress, system, result, context, error, &
                          contact=contact)
        if (allocated(error)) return
        ! With creep the start stresses less the stresses the increment's creep relaxes: the
        ! creep load joins the out-of-balance force (cfrd_creep_step).
        rhs_stress = state%stress
        if (allocated(state%creep_stress)) rhs_stress = rhs_stress - state%creep_stress
        call solve_out_of_balance(model, library, state, rhs_stress, f_target, du_prescribed, &
                                  system, du, result, context, error, contact)
        if (allocated(error)) return
        if (model%solver == solver_euler .or. system%factorised_linear .or. &
            (state%has_contact .and. all_linear(model, state%active))) then
            ! Euler; or a linear law, for which the midpoint step would repeat the same solve.
            call integrate_stress(model, library, state, du, stress_end, stress_mid, .false., &
                                  creep_share=1.0_dp)
        else
            ! Midpoint: stresses half-way, the tangent there, and the increment again.
            call integrate_stress(model, library, state, 0.5_dp*du, stress_mid, stress_end, &
                                  .false., creep_share=0.5_dp)
            call factorise_at(model, library, state, stress_mid, system, result, context, &
                              error, contact=contact)
            if (allocated(error)) return
            call solve_out_of_balance(model, library, state, rhs_stress, f_target, &
                                      du_prescribed, system, du, result, context, error, contact)
            if (allocated(error)) return
            call integrate_stress(model, library, state, du, stress_end, stress_mid, .true., &
                                  creep_share=1.0_dp)
        end if
        residual = out_of_balance(model, library, state%active, stress_end, f_target, &
                                  system%dofmap, contact)/load_norm
        if (model%solver == solver_newton) then
            iteration = 0
            recent = huge(1.0_dp)
            do while (residual > model%tolerance)
                iteration = iteration + 1
                ! A stall (the residual not halved over the last four iterations) ends the
                ! iterations early, so that a cutback can be tried without waste.
                if (mod(iteration, 4) == 1) then
                    if (iteration > 1 .and. residual > 0.5_dp*recent) then
                        call fatal_error(error, context//': no convergence: Newton '// &
                                         'iterations stalled at iteration '// &
                                         to_text(iteration - 1)//' (relative residual '// &
                                         real_text(residual)//', tolerance '// &
                                         real_text(model%tolerance)//'; largest out-of-'// &
                                         'balance force at '//worst_node()//')', &
                                         numerical_error)
                        return
                    end if
                    recent = residual
                end if
                if (iteration > model%max_iterations) then
                    call fatal_error(error, context//': no convergence after '// &
                                     to_text(model%max_iterations)//' Newton iterations '// &
                                     '(relative residual '//real_text(residual)//', tolerance '// &
                                     real_text(model%tolerance)//'; largest out-of-balance '// &
                                     'force at '//worst_node()//')', numerical_error)
                    return
                end if
                ! The consistent tangent: the derivative of the midpoint stress update with
                ! respect to the strain increment, by finite differences at each point.
                call factorise_at(model, library, state, stress_mid, system, result, context, &
                                  error, consistent_tangents(model, library, state, du), contact)
                if (allocated(error)) return
                block
                    real(dp), allocatable :: ddu(:, :), du_try(:, :), stress_try(:, :, :)
                    real(dp) :: step, trial
                    integer :: halving
                    call solve_out_of_balance(model, library, state, stress_end, f_target, &
                                              0.0_dp*du_prescribed, system, ddu, result, &
                                              context, error, contact, du)
                    if (allocated(error)) return
                    ! Backtracking line search: the E-B tangent has kinks (stress-level cap,
                    ! sigma3 floor, Poisson bounds, unloading transition) where a full
                    ! Newton step can overshoot; halve it while the residual grows. Not with
                    ! contact: the multipliers belong to the full step.
                    step = 1.0_dp
                    do halving = 0, 6
                        du_try = du + step*ddu
                        call integrate_stress(model, library, state, du_try, stress_try, &
                                              stress_mid, .true., creep_share=1.0_dp)
                        trial = out_of_balance(model, library, state%active, stress_try, &
                                               f_target, system%dofmap, contact)/load_norm
                        if (trial < residual .or. state%has_contact) exit
                        step = 0.5_dp*step
                    end do
                    du = du_try
                    stress_end = stress_try
                    residual = trial
                end block
                result%iterations = result%iterations + 1
            end do
        end if
        if (.not. (residual < huge(1.0_dp))) then
            call fatal_error(error, context//': the solution is not finite', numerical_error)
            return
        end if
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

    !> du = du_p + K^-1 (f_target - f_int(stress + D B du_p)) on the free dofs: the prescribed
    !> increment du_p moves the fixed dofs, and the forces it causes (K_fp du_p, through the
    !> tangent at `stress`) join the out-of-balance force. With contact the multipliers are
    !> solved with du, and the active set is iterated until it holds (primal-dual active set,
    !> docs/theory.md section 14); `du_base` is the increment already taken (Newton).
    subroutine solve_out_of_balance(model, library, state, stress, f_target, du_p, system, &
                                    du, result, context, error, contact, du_base)
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
        real(dp), allocatable :: f_int(:, :), b(:), x(:), known(:, :)
        integer, allocatable :: seen(:, :), before(:), flips(:)
        logical, allocatable :: held(:), changing(:)
        real(dp) :: t0
        integer :: node, k, c, neq, iteration, earlier, cycling, since
        logical :: changed, released
        allocate (f_int(2, model%mesh%nnode))
        if (any(du_p /= 0.0_dp)) then
            call internal_forces(model, library, state%active, &
                                 stress_after(model, library, state, stress, du_p), f_int)
        else
            call internal_forces(model, library, state%active, stress, f_int)
        end if
        neq = system%dofmap%neq
        allocate (b(system%pattern%n), x(system%pattern%n))
        do node = 1, model%mesh%nnode
            do k = 1, 2
                if (system%dofmap%eq(k, node) > 0) b(system%dofmap%eq(k, node)) = &
                    f_target(k, node) - f_int(k, node)
            end do
        end do
        if (present(contact)) then
            known = du_p
            if (present(du_base)) known = known + du_base
            allocate (seen(contact%nc, contact_iteration_limit))
            allocate (flips(contact%nc), source=0)
            allocate (held(contact%nc), source=.false.)
        end if
        iteration = 0
        cycling = 0
        since = 1
        released = .false.
        do
            iteration = iteration + 1
            if (present(contact)) then
                do c = 1, contact%nc
                    b(neq + 2*c - 1:neq + 2*c) = merge(contact_rhs(contact, c, &
                        system%contact_scale, known, system%viscous), 0.0_dp, &
                        system%constrains(:, c))
                end do
            end if
            t0 = wall_seconds()
            call system%solver%solve(system%pattern, system%values, b, x, error)
            result%stats%t_solve = result%stats%t_solve + (wall_seconds() - t0)
            if (allocated(error) .and. system%solver%is_updated()) then
                ! An updated solve that did not reach UMFPACK's accuracy: factorise instead.
                deallocate (error)
                result%stats%updates_declined = result%stats%updates_declined + 1
                call factorise_contact(model, system, contact, result, context, error, .false.)
                if (allocated(error)) return
                t0 = wall_seconds()
                call system%solver%solve(system%pattern, system%values, b, x, error)
                result%stats%t_solve = result%stats%t_solve + (wall_seconds() - t0)
            end if
            if (allocated(error)) then
                error%message = context//': '//error%message
                return
            end if
            if (.not. all(ieee_is_finite(x))) then
                call fatal_error(error, context//': the solution is not finite (singular '// &
                                 'stiffness matrix?)', numerical_error)
                return
            end if
            du = du_p
            do node = 1, model%mesh%nnode
                do k = 1, 2
                    if (system%dofmap%eq(k, node) > 0) du(k, node) = x(system%dofmap%eq(k, node))
                end do
            end do
            if (.not. present(contact)) exit
            ! The active set: done when the solve left it as it was.
            t0 = wall_seconds()
            call contact_unpack(contact, x(neq + 1:), system%contact_scale)
            before = 3*contact%status + contact%slip_sign
            call update_sets()
            result%stats%t_contact = result%stats%t_contact + (wall_seconds() - t0)
            result%stats%contact_iterations = result%stats%contact_iterations + 1
            if (.not. changed .and. any(held)) then
                ! Held nodes: accepted when their tractions break stick by little; else
                ! released once, the iteration going on as without holds.
                call check_held(error)
                if (.not. allocated(error) .or. released .or. &
                    iteration == contact_iteration_limit) return
                deallocate (error)
                held = .false.
                released = .true.
                call update_sets()
            end if
            if (.not. changed) return
            seen(:, iteration) = 3*contact%status + contact%slip_sign
            where (seen(:, iteration) /= before) flips = flips + 1
            ! Chatter (a node that keeps changing, never repeating the whole set exactly):
            ! hold it closed in stick (docs/theory.md section 14).
            if (iteration >= chatter_start .and. .not. released .and. &
                any(flips >= chatter_flips .and. .not. held)) then
                where (flips >= chatter_flips) held = .true.
                since = iteration
            end if
            do earlier = since, iteration - 1
                if (all(seen(:, earlier) == seen(:, iteration))) then
                    ! A cycle: go on changing one node at a time (the worst first), once;
                    ! a second one: hold the nodes that change within it, once more.
                    changing = [(any(seen(c, earlier:iteration) /= seen(c, iteration)), &
                                 c=1, contact%nc)]
                    if (cycling == 0) then
                        cycling = iteration
                        since = iteration
                        exit
                    end if
                    if (released .or. .not. any(changing .and. .not. held)) then
                        call fatal_error(error, context//': no convergence: the contact '// &
                                         'active set cycles at contact iteration '// &
                                         to_text(iteration)//' (it repeats iteration '// &
                                         to_text(earlier)//') with '// &
                                         to_text(count(changing))//' slave nodes held; '// &
                                         worst_text(changing), numerical_error)
                        return
                    end if
                    where (changing) held = .true.
                    since = iteration
                    exit
                end if
            end do
            if (iteration == contact_iteration_limit) then
                call fatal_error(error, context//': no convergence: the contact active set '// &
                                 'did not settle in '//to_text(iteration)//' iterations ('// &
                                 to_text(count(seen(:, iteration) /= before))// &
                                 ' slave nodes changed in the last, '// &
                                 to_text(count(held))//' held in stick; '// &
                                 worst_text(seen(:, iteration) /= before), numerical_error)
                return
            end if
            call factorise_contact(model, system, contact, result, context, error, .true.)
            if (allocated(error)) return
        end do
    contains
        subroutine update_sets()
            if (present(du_base)) then
                call contact_update_sets(model, contact, du_base + du, system%contact_scale, &
                                         changed, cycling > 0, held)
            else
                call contact_update_sets(model, contact, du, system%contact_scale, changed, &
                                         cycling > 0, held)
            end if
        end subroutine update_sets

        !> The held nodes' excess over their stick conditions against held_tolerance times
        !> the largest contact pressure; counted in the stage's results, or an error.
        subroutine check_held(error)
            type(error_t), allocatable, intent(out) :: error
            real(dp), allocatable :: excess(:)
            real(dp) :: bound
            integer :: worst
            allocate (excess(size(held)), source=0.0_dp)
            do c = 1, contact%nc
                if (held(c) .and. contact%supported(c)) &
                    excess(c) = contact_stick_excess(model, contact, c)
            end do
            bound = held_tolerance*max(maxval(abs(contact%p)), tiny(1.0_dp))
            worst = maxloc(excess, dim=1)
            if (excess(worst) > bound) then
                call fatal_error(error, context//': no convergence: '//to_text(count(held))// &
                                 ' slave nodes held in stick after chatter or a cycle '// &
                                 '(contact iteration '//to_text(iteration)//') break '// &
                                 'their conditions: node '// &
                                 to_text(contact%node(worst))//' by '// &
                                 real_text(excess(worst))//' kPa (p '// &
                                 real_text(contact%p(worst))//', q '// &
                                 real_text(contact%q(worst))//' kPa), more than '// &
                                 real_text(held_tolerance)//' of the largest pressure '// &
                                 real_text(maxval(abs(contact%p)))//' kPa', numerical_error)
                return
            end if
            result%stats%held = max(result%stats%held, count(held))
            result%stats%held_excess = max(result%stats%held_excess, &
                                           excess(worst)/max(maxval(abs(contact%p)), &
                                                             tiny(1.0_dp)))
        end subroutine check_held

        !> 'node N (status from -> to, complementarity violation V kPa)' for the node of
        !> `mask` that violates its conditions most (its excess over stick, or |p| when open).
        function worst_text(mask) result(text)
            logical, intent(in) :: mask(:)
            character(len=:), allocatable :: text
            real(dp), allocatable :: measure(:)
            integer :: worst
            allocate (measure(size(mask)), source=-1.0_dp)
            do c = 1, contact%nc
                if (mask(c)) measure(c) = max(contact_stick_excess(model, contact, c), &
                                              abs(contact%p(c)))
            end do
            worst = maxloc(measure, dim=1)
            text = 'the first of them node '// &
                   to_text(contact%node(findloc(mask, .true., dim=1)))// &
                   ', the worst node '//to_text(contact%node(worst))//' (p '// &
                   real_text(contact%p(worst))//', q '//real_text(contact%q(worst))// &
                   ' kPa, status '//status_word(before(worst))//' -> '// &
                   status_word(3*contact%status(worst) + contact%slip_sign(worst))//')'
        end function worst_text
    end subroutine solve_out_of_balance

    pure function status_word(code) result(word)
        integer, intent(in) :: code
        character(len=:), allocatable :: word
        select case (code)
        case (0)
            word = 'open'
        case (3)
            word = 'stick'
        case (5)
            word = 'slip-'
        case (7)
            word = 'slip+'
        case default
            word = 'slip'
        end select
    end function status_word

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
        associate (element => library(model%mesh%kind(e))%element)
            nn = element%nodes()
            ng = element%gauss_points()
            nc = element%components()
            strain = 0.0_dp
            call element%strains(model%mesh%x(:, model%mesh%conn(1:nn, e)), &
                                 gather(model, e, nn, du), strain(1:nc, 1:ng))
        end associate
    end subroutine element_strains

    !> Stresses after the displacement increment du from `stress` (the state's stresses
    !> when absent): each point's law integrates its strain increment, with the tangent at
    !> the midpoint when `midpoint` (docs/theory.md sections 9 and 12). `stress_mid`
    !> returns the half-way stresses of that integration.
    subroutine integrate_stress(model, library, state, du, stress_end, stress_mid, midpoint, &
                                stress, creep_share)
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
        real(dp) :: strain(4, ngauss), start(4)
        integer :: e, ng, ig
        logical :: creeping
        if (present(stress)) then
            stress_end = stress
        else
            stress_end = state%stress
        end if
        stress_mid = stress_end
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
                call material_update(model%materials(model%mesh%material(e)), model%pa, &
                                     start, state%strain(:, ig, e), &
                                     state%history(:, ig, e), strain(:, ig), midpoint, &
                                     stress_end(:, ig, e), stress_mid(:, ig, e))
                if (creeping) stress_end(:, ig, e) = stress_end(:, ig, e) - &
                                                     0.5_dp*creep_share* &
                                                     state%creep_stress(:, ig, e)
            end do
        end do
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

    !> d sigma_end / d(delta eps) of the stress update at every point of the active elements
    !> (cfrd_material_law: material_update_tangent), Newton's tangent.
    function consistent_tangents(model, library, state, du) result(c)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        real(dp), intent(in) :: du(:, :)
        real(dp), allocatable :: c(:, :, :, :)
        real(dp) :: strain(4, ngauss)
        integer :: e, ng, ig
        allocate (c(4, 4, ngauss, model%mesh%nelem), source=0.0_dp)
        do e = 1, model%mesh%nelem
            if (.not. state%active(e)) cycle
            call element_strains(model, library, e, du, strain, ng)
            do ig = 1, ng
                call material_update_tangent(model%materials(model%mesh%material(e)), &
                                             model%pa, state%stress(:, ig, e), &
                                             state%strain(:, ig, e), state%history(:, ig, e), &
                                             strain(:, ig), c(:, :, ig, e))
            end do
        end do
    end function consistent_tangents

    !> |f_target - f_int(stress)| over the free dofs.
    function out_of_balance(model, library, active, stress, f_target, dofmap, contact, &
                            worst) result(norm)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        real(dp), intent(in) :: stress(:, :, :), f_target(:, :)
        type(dof_map_t), intent(in) :: dofmap
        type(contact_t), intent(in), optional :: contact
        !> 'node N (fx, fy kN/m)': the node of the largest out-of-balance force
        character(len=:), allocatable, intent(out), optional :: worst
        real(dp) :: norm
        real(dp), allocatable :: f_int(:, :), f_contact(:, :), r(:, :)
        integer :: node
        allocate (f_int(2, model%mesh%nnode))
        call internal_forces(model, library, active, stress, f_int)
        if (present(contact)) then
            allocate (f_contact(2, model%mesh%nnode))
            call contact_forces(contact, f_contact)
            f_int = f_int - f_contact
        end if
        r = merge(f_target - f_int, 0.0_dp, dofmap%eq > 0)
        norm = norm2(r)
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
        do e = 1, model%mesh%nelem
            if (.not. state%active(e)) cycle
            call element_strains(model, library, e, du, strain, ng)
            state%strain(:, 1:ng, e) = state%strain(:, 1:ng, e) + strain(:, 1:ng)
            do ig = 1, ng
                call update_history(model%materials(model%mesh%material(e)), model%pa, &
                                    state%stress(:, ig, e), state%history(:, ig, e))
            end do
        end do
    end subroutine accept_history

    !> The stage's results: displacements, stresses, principal stresses, reactions.
    subroutine record(model, library, state, result)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(state_t), intent(in) :: state
        type(stage_result_t), intent(inout) :: result
        real(dp), allocatable :: f_int(:, :)
        logical, allocatable :: used(:)
        integer :: e, ig, ng
        associate (mesh => model%mesh)
            result%active = state%active
            allocate (result%stress_level(mesh%nelem), source=0.0_dp)
            do e = 1, mesh%nelem
                if (.not. state%active(e)) cycle
                do ig = 1, library(mesh%kind(e))%element%gauss_points()
                    result%stress_level(e) = max(result%stress_level(e), stress_level( &
                        model%materials(mesh%material(e)), model%pa, state%stress(:, ig, e), &
                        state%history(:, ig, e)))
                end do
            end do
            ! Near failure: stress level 0.95 or more (the law caps it at 0.99).
            result%near_failure = count(result%stress_level >= 0.95_dp)
            result%displacement = state%u
            result%displacement_total = state%u_before_reset + state%u
            result%stress_gauss = state%stress
            result%strain_gauss = state%strain
            result%history_gauss = state%history
            if (allocated(state%creep)) result%creep_gauss = state%creep
            if (allocated(model%interfaces)) then
                call interface_stations(model, state%stress, state%strain, state%active, &
                                        result%interface)
                call phase_openings(model, result%interface, result%openings)
            end if
            if (allocated(model%slab_groups)) &
                call slab_stresses(model, state%stress, state%active, result%slab)
            allocate (result%stress_centroid(4, mesh%nelem), result%principal(3, mesh%nelem))
            do e = 1, mesh%nelem
                ng = library(mesh%kind(e))%element%gauss_points()
                result%stress_centroid(:, e) = sum(state%stress(:, 1:ng, e), dim=2)/ng
                result%principal(:, e) = 0.0_dp
                ! Principal stresses of solids; a joint's (sigma_n, tau) have none.
                if (library(mesh%kind(e))%element%components() == 4) &
                    result%principal(:, e) = principal_stresses(result%stress_centroid(:, e))
            end do
            allocate (f_int(2, mesh%nnode))
            call internal_forces(model, library, state%active, state%stress, f_int)
            if (state%has_contact) then
                ! contact forces are internal to the model: reactions see their sum
                block
                    real(dp), allocatable :: f_contact(:, :)
                    allocate (f_contact(2, mesh%nnode))
                    call contact_forces(state%contact, f_contact)
                    f_int = f_int - f_contact
                end block
                call record_contact(model, state%contact, state%active, result%contact, &
                                    result%openings)
            end if
            used = active_nodes(model, state%active)
            result%reaction = merge(f_int - state%f_ext, 0.0_dp, &
                                    model%fixed .and. spread(used, 1, 2))
            result%applied_load = sum(state%f_ext, dim=2)
            result%reaction_sum = sum(result%reaction, dim=2)
        end associate
    end subroutine record


end module cfrd_stage_driver
