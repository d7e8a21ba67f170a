!> The solve of one linearised system with the contact active set iterated until it holds
!> (primal-dual active set with Coulomb friction, docs/theory.md section 14): chatter and
!> cycles of the set are broken by holding nodes in stick, and accepted only when the held
!> nodes break their conditions by little.
module cfrd_active_set
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, numerical_error
    use cfrd_clock, only: wall_seconds
    use cfrd_strings, only: to_text, real_text
    use cfrd_model, only: model_t
    use cfrd_results, only: stage_result_t
    use cfrd_contact, only: contact_t, contact_iteration_limit
    use cfrd_contact_constraints, only: contact_rhs, contact_unpack, contact_update_sets, &
                                        contact_stick_excess, contact_shear_shape
    use cfrd_linear_system, only: system_t, factorise_contact
    implicit none
    private

    public :: solve_system


    !> A slave node whose status changes this often in one solve chatters: it is held in
    !> stick (docs/theory.md section 14).
    integer, parameter :: chatter_flips = 4
    !> ... once the iteration has run this long without settling (half the limit): the
    !> chatter of converging iterations is left alone.
    integer, parameter :: chatter_start = contact_iteration_limit/2
    !> Held nodes are accepted when no one's excess over its stick conditions (tension, or
    !> shear beyond mu p) exceeds this fraction of the largest contact pressure.
    real(dp), parameter :: held_tolerance = 1.0e-3_dp
    !> Friction groups: a solve whose pressures move a group's shear shape by more than
    !> this is solved again with the new shape, at most shape_passes times [choice].
    real(dp), parameter :: shape_tolerance = 0.05_dp
    integer, parameter :: shape_passes = 3


contains

    !> du = du_p + K^-1 r on the free dofs, r the out-of-balance force `rhs` (2, nnode) given
    !> by the caller (f_target - f_int, with the forces of the prescribed increment du_p in
    !> it). With contact the multipliers are solved with du, and the active set is iterated
    !> until it holds (primal-dual active set, docs/theory.md section 14); `du_base` is the
    !> increment already taken (Newton). `unsettled`: the error is the active set's failure to
    !> converge (a cycle, the iteration limit, held nodes breaking stick), which a smaller
    !> step may cure (the stage driver cuts the increment back).
    subroutine solve_system(model, rhs, du_p, system, du, result, context, error, contact, &
                            du_base, unsettled)
        type(model_t), intent(in) :: model
        real(dp), intent(in) :: rhs(:, :), du_p(:, :)
        type(system_t), intent(inout) :: system
        real(dp), allocatable, intent(out) :: du(:, :)
        type(stage_result_t), intent(inout) :: result
        character(len=*), intent(in) :: context
        type(error_t), allocatable, intent(out) :: error
        type(contact_t), intent(inout), optional :: contact
        real(dp), intent(in), optional :: du_base(:, :)
        logical, intent(out), optional :: unsettled
        real(dp), allocatable :: b(:), x(:), known(:, :)
        integer, allocatable :: seen(:, :), before(:), flips(:)
        logical, allocatable :: held(:), changing(:)
        real(dp) :: t0
        integer :: node, k, c, neq, iteration, earlier, cycling, since, passes
        logical :: changed, released
        if (present(unsettled)) unsettled = .false.
        neq = system%dofmap%neq
        allocate (b(system%pattern%n), x(system%pattern%n))
        do node = 1, model%mesh%nnode
            do k = 1, 2
                if (system%dofmap%eq(k, node) > 0) b(system%dofmap%eq(k, node)) = rhs(k, node)
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
        passes = 0
        cycling = 0
        since = 1
        released = .false.
        do
            iteration = iteration + 1
            if (present(contact)) then
                do c = 1, contact%nc
                    b(neq + 2*c - 1:neq + 2*c) = contact_rhs(contact, c, &
                        system%contact_scale, known, system%viscous, system%constrains)
                end do
            end if
            ! With contact, the multipliers and the contact surfaces' displacements first:
            ! the rest once the active set has settled (complete, below).
            call timed_solve(.false.)
            if (allocated(error) .and. system%solver%is_updated()) then
                ! An updated solve that did not reach UMFPACK's accuracy: factorise instead.
                deallocate (error)
                result%stats%updates_declined = result%stats%updates_declined + 1
                call factorise_contact(model, system, contact, result, context, error, .false.)
                if (allocated(error)) return
                call timed_solve(.false.)
            end if
            if (.not. solved()) return
            call unpack_displacements()
            if (.not. present(contact)) exit
            ! The active set: done when the solve left it as it was. Its test reads the
            ! contact surfaces' motion (weighted_motion) and the multipliers only.
            t0 = wall_seconds()
            call contact_unpack(contact, x(neq + 1:), system%contact_scale)
            before = 3*contact%status + contact%slip_sign
            call update_sets()
            result%stats%t_contact = result%stats%t_contact + (wall_seconds() - t0)
            result%stats%contact_iterations = result%stats%contact_iterations + 1
            if (.not. changed) then
                ! Settled (or about to be held or reshaped): the whole solution
                call timed_solve(.true.)
                if (.not. solved()) return
                call unpack_displacements()
            end if
            if (.not. changed .and. any(held)) then
                ! Held nodes: accepted when their tractions break stick by little; else
                ! released once, the iteration going on as without holds.
                call check_held(error)
                if (allocated(error) .and. present(unsettled)) unsettled = .true.
                if (.not. allocated(error) .or. released .or. &
                    iteration == contact_iteration_limit) return
                if (present(unsettled)) unsettled = .false.
                deallocate (error)
                held = .false.
                released = .true.
                call update_sets()
            end if
            if (.not. changed) then
                if (.not. reshaped()) return
                call factorise_contact(model, system, contact, result, context, error, .true.)
                if (allocated(error)) return
                cycle
            end if
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
                        if (present(unsettled)) unsettled = .true.
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
                if (present(unsettled)) unsettled = .true.
                return
            end if
            call factorise_contact(model, system, contact, result, context, error, .true.)
            if (allocated(error)) return
        end do
    contains
        !> x for b, partial with contact (`completing` false), or the rest of the last
        !> partial solve (true); its time counted as the solve's.
        subroutine timed_solve(completing)
            logical, intent(in) :: completing
            real(dp) :: t
            t = wall_seconds()
            if (completing) then
                call system%solver%complete(x, error)
            else
                call system%solver%solve(system%pattern, system%values, b, x, error, &
                                         partial=present(contact))
            end if
            result%stats%t_solve = result%stats%t_solve + (wall_seconds() - t)
        end subroutine timed_solve

        !> The solve succeeded and x is finite; else `error` says which, in its context.
        logical function solved()
            solved = .false.
            if (allocated(error)) then
                error%message = context//': '//error%message
                return
            end if
            if (.not. all(ieee_is_finite(x))) then
                call fatal_error(error, context//': the solution is not finite (singular '// &
                                 'stiffness matrix?)', numerical_error)
                return
            end if
            solved = .true.
        end function solved

        !> du: the prescribed increment and the solved equations of x
        subroutine unpack_displacements()
            du = du_p
            do node = 1, model%mesh%nnode
                do k = 1, 2
                    if (system%dofmap%eq(k, node) > 0) du(k, node) = x(system%dofmap%eq(k, node))
                end do
            end do
        end subroutine unpack_displacements

        !> The friction groups' shear shapes from the pressures of this solve: true (and the
        !> new shapes kept, to be solved with) when one moved by more than shape_tolerance,
        !> at most shape_passes times per solve (docs/theory.md section 14).
        logical function reshaped()
            real(dp), allocatable :: old(:)
            reshaped = .false.
            if (contact%ngroup == 0 .or. passes >= shape_passes .or. &
                iteration >= contact_iteration_limit - 1) return
            old = contact%beta
            call contact_shear_shape(contact)
            reshaped = maxval(abs(contact%beta - old)) > shape_tolerance
            if (.not. reshaped) contact%beta = old
            if (reshaped) passes = passes + 1
        end function reshaped

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
    end subroutine solve_system

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

end module cfrd_active_set
