!> The analysis state at a stage's end and its stored form (docs/results.md, "Restart"):
!> carry_of keeps in a stage's result what the stage's own fields do not hold (the
!> displacements before the last RESET, the applied load, the wetted elements, the contact
!> state and the scale of its multipliers); restore_state rebuilds the state from a stored
!> stage, so that the next stage starts as it did in the run that stored it.
module cfrd_restart_carry
    use cfrd_kinds, only: dp
    use cfrd_results, only: stage_result_t, carry_t
    use cfrd_contact, only: contact_t
    use cfrd_stage_state, only: state_t
    implicit none
    private

    public :: carry_of, restore_state

contains

    !> The part of `state` a stage's result does not hold, with the multiplier scale of
    !> the linear system in use.
    function carry_of(state, contact_scale) result(carry)
        type(state_t), intent(in) :: state
        real(dp), intent(in) :: contact_scale
        type(carry_t) :: carry
        type(contact_t) :: contact
        carry%u_before_reset = state%u_before_reset
        carry%f_ext = state%f_ext
        carry%prescribed_done = state%prescribed_done
        if (allocated(state%wetted)) carry%wetted = state%wetted
        carry%contact_scale = contact_scale
        if (.not. state%has_contact) return
        contact = state%contact
        call carry_contact(contact, carry, save=.true.)
    end function carry_of

    !> The contact state between `c` and `carry`: into the carry (`save`) or back into `c`;
    !> one list of the fields for both ways.
    subroutine carry_contact(c, carry, save)
        type(contact_t), intent(inout) :: c
        type(carry_t), intent(inout) :: carry
        logical, intent(in) :: save
        if (save) then
            carry%searches = c%searches
            carry%ngroup = c%ngroup
        else
            c%searches = carry%searches
            c%ngroup = carry%ngroup
        end if
        call move_l(c%placed, carry%placed, save)
        call move_l(c%supported, carry%supported, save)
        call move_l(c%seg_searched, carry%seg_searched, save)
        call move_l(c%mseg_searched, carry%mseg_searched, save)
        call move_i(c%status, carry%status, save)
        call move_i(c%slip_sign, carry%slip_sign, save)
        call move_i(c%birth, carry%birth, save)
        call move_i(c%cpl_ptr, carry%cpl_ptr, save)
        call move_i(c%cpl_node, carry%cpl_node, save)
        call move_r(c%cpl_a, carry%cpl_a, save)
        call move_r(c%p, carry%p, save)
        call move_r(c%q, carry%q, save)
        call move_r(c%g0, carry%g0, save)
        call move_r(c%gap, carry%gap, save)
        call move_r(c%slip, carry%slip, save)
        call move_r(c%w, carry%w, save)
        call move_r(c%wref, carry%wref, save)
        call move_r(c%g, carry%g, save)
        call move_r(c%g_curve, carry%g_curve, save)
        call move_r2(c%u, carry%u, save)
        call move_r2(c%normal, carry%normal, save)
        call move_r2(c%tangent, carry%tangent, save)
        call move_i(c%tgroup, carry%tgroup, save)
        call move_i(c%grp_ptr, carry%grp_ptr, save)
        call move_i(c%grp_node, carry%grp_node, save)
        call move_r(c%beta, carry%beta, save)
    end subroutine carry_contact

    !> The state at the end of the stored stage `stage` (its fields and carry as read back):
    !> `state` comes from the stage driver's initial state (its arrays allocated, the contact
    !> surfaces built) and every evolving part of it is replaced.
    subroutine restore_state(stage, state)
        type(stage_result_t), intent(inout) :: stage
        type(state_t), intent(inout) :: state
        state%u = stage%displacement
        state%stress = stage%stress_gauss
        state%strain = stage%strain_gauss
        state%active = stage%active
        state%level = stage%water_level
        state%day = stage%day
        ! a light stage (cfrd_stage_driver: stored_interface) leaves the rest out
        if (allocated(stage%history_gauss)) state%history = stage%history_gauss
        if (allocated(state%creep) .and. allocated(stage%creep_gauss)) &
            state%creep = stage%creep_gauss
        if (allocated(state%wet) .and. allocated(stage%wetting_gauss)) &
            state%wet = stage%wetting_gauss
        if (allocated(state%creep_stress)) state%creep_stress = 0.0_dp
        associate (carry => stage%carry)
            state%u_before_reset = carry%u_before_reset
            if (allocated(carry%f_ext)) state%f_ext = carry%f_ext
            state%prescribed_done = carry%prescribed_done
            if (allocated(state%wetted)) state%wetted = carry%wetted
        end associate
        if (state%has_contact) call carry_contact(state%contact, stage%carry, save=.false.)
    end subroutine restore_state

    !> a = b (`save`: b = a), when the source is allocated.
    subroutine move_l(a, b, save)
        logical, allocatable, intent(inout) :: a(:), b(:)
        logical, intent(in) :: save
        if (save .and. allocated(a)) b = a
        if (.not. save .and. allocated(b)) a = b
    end subroutine move_l

    !> a = b (`save`: b = a), when the source is allocated.
    subroutine move_i(a, b, save)
        integer, allocatable, intent(inout) :: a(:), b(:)
        logical, intent(in) :: save
        if (save .and. allocated(a)) b = a
        if (.not. save .and. allocated(b)) a = b
    end subroutine move_i

    !> a = b (`save`: b = a), when the source is allocated.
    subroutine move_r(a, b, save)
        real(dp), allocatable, intent(inout) :: a(:), b(:)
        logical, intent(in) :: save
        if (save .and. allocated(a)) b = a
        if (.not. save .and. allocated(b)) a = b
    end subroutine move_r

    subroutine move_r2(a, b, save)
        real(dp), allocatable, intent(inout) :: a(:, :), b(:, :)
        logical, intent(in) :: save
        if (save .and. allocated(a)) b = a
        if (.not. save .and. allocated(b)) a = b
    end subroutine move_r2
end module cfrd_restart_carry
