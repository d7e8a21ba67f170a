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
        carry%u_before_reset = state%u_before_reset
        carry%f_ext = state%f_ext
        carry%prescribed_done = state%prescribed_done
        if (allocated(state%wetted)) carry%wetted = state%wetted
        carry%contact_scale = contact_scale
        if (state%has_contact) call carry_contact(state%contact, carry)
    end function carry_of

    subroutine carry_contact(c, carry)
        type(contact_t), intent(in) :: c
        type(carry_t), intent(inout) :: carry
        carry%searches = c%searches
        carry%placed = c%placed
        carry%supported = c%supported
        if (allocated(c%seg_searched)) carry%seg_searched = c%seg_searched
        if (allocated(c%mseg_searched)) carry%mseg_searched = c%mseg_searched
        carry%status = c%status
        carry%slip_sign = c%slip_sign
        carry%birth = c%birth
        carry%cpl_ptr = c%cpl_ptr
        carry%cpl_node = c%cpl_node
        carry%cpl_a = c%cpl_a
        carry%p = c%p
        carry%q = c%q
        carry%g0 = c%g0
        carry%gap = c%gap
        carry%slip = c%slip
        carry%w = c%w
        carry%wref = c%wref
        carry%g = c%g
        if (allocated(c%g_curve)) carry%g_curve = c%g_curve
        carry%u = c%u
        carry%normal = c%normal
        carry%tangent = c%tangent
    end subroutine carry_contact

    !> The state at the end of the stored stage `stage` (its fields and carry as read back):
    !> `state` comes from the stage driver's initial state (its arrays allocated, the contact
    !> surfaces built) and every evolving part of it is replaced.
    subroutine restore_state(stage, state)
        type(stage_result_t), intent(in) :: stage
        type(state_t), intent(inout) :: state
        state%u = stage%displacement
        state%stress = stage%stress_gauss
        state%strain = stage%strain_gauss
        state%history = stage%history_gauss
        state%active = stage%active
        state%level = stage%water_level
        state%day = stage%day
        if (allocated(state%creep)) state%creep = stage%creep_gauss
        if (allocated(state%wet)) state%wet = stage%wetting_gauss
        if (allocated(state%creep_stress)) state%creep_stress = 0.0_dp
        associate (carry => stage%carry)
            state%u_before_reset = carry%u_before_reset
            state%f_ext = carry%f_ext
            state%prescribed_done = carry%prescribed_done
            if (allocated(state%wetted)) state%wetted = carry%wetted
            if (state%has_contact) call restore_contact(carry, state%contact)
        end associate
    end subroutine restore_state

    subroutine restore_contact(carry, c)
        type(carry_t), intent(in) :: carry
        type(contact_t), intent(inout) :: c
        c%searches = carry%searches
        c%placed = carry%placed
        c%supported = carry%supported
        if (allocated(carry%seg_searched)) c%seg_searched = carry%seg_searched
        if (allocated(carry%mseg_searched)) c%mseg_searched = carry%mseg_searched
        c%status = carry%status
        c%slip_sign = carry%slip_sign
        c%birth = carry%birth
        c%cpl_ptr = carry%cpl_ptr
        c%cpl_node = carry%cpl_node
        c%cpl_a = carry%cpl_a
        c%p = carry%p
        c%q = carry%q
        c%g0 = carry%g0
        c%gap = carry%gap
        c%slip = carry%slip
        c%w = carry%w
        c%wref = carry%wref
        c%g = carry%g
        if (allocated(carry%g_curve)) c%g_curve = carry%g_curve
        c%u = carry%u
        c%normal = carry%normal
        c%tangent = carry%tangent
    end subroutine restore_contact
end module cfrd_restart_carry
