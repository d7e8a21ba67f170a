!> Which surface of a contact pair carries the multipliers (docs/theory.md section 14,
!> "Roles"): a slave much finer than its master makes the mortar's multiplier space too rich
!> for the master's motion (its multipliers are not controlled: the inf-sup condition is
!> lost as the ratio grows), so the finer surface is made the master and the coarser one
!> carries the multipliers (Puso & Laursen 2004; Popp et al. 2009) [lit]; PAIR field ROLES
!> ASIS keeps the roles as given.
module cfrd_contact_roles
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, contact_pair_t, scheme_mortar
    implicit none
    private

    public :: assign_roles, mean_face, role_swap_ratio

    !> A slave whose mean face is this many times shorter than its master's is "much finer"
    !> (the ratio at which cfrd_contact's friction groups start) [choice]
    real(dp), parameter :: role_swap_ratio = 3.0_dp

contains

    !> The roles of `pair` (as read from its card): a MORTAR pair whose slave's mean face is
    !> role_swap_ratio or more times shorter than its master's (coordinates of the deck)
    !> is swapped, unless ROLES ASIS.
    pure subroutine assign_roles(model, pair)
        type(model_t), intent(in) :: model
        type(contact_pair_t), intent(inout) :: pair
        integer :: finer
        pair%swapped = .false.
        if (pair%roles_asis .or. pair%scheme /= scheme_mortar) return
        if (mean_face(model, pair%master) < role_swap_ratio*mean_face(model, pair%slave)) return
        finer = pair%slave
        pair%slave = pair%master
        pair%master = finer
        pair%swapped = .true.
    end subroutine assign_roles

    !> The mean length of the faces of surface k at the coordinates of the deck.
    pure real(dp) function mean_face(model, k)
        type(model_t), intent(in) :: model
        integer, intent(in) :: k
        integer :: j, e, f
        mean_face = 0.0_dp
        associate (surface => model%surfaces(k), mesh => model%mesh)
            do j = 1, size(surface%element)
                e = surface%element(j)
                f = surface%face(j)
                mean_face = mean_face + norm2(mesh%x(:, mesh%conn(mod(f, 4) + 1, e)) - &
                                              mesh%x(:, mesh%conn(f, e)))
            end do
            mean_face = mean_face/max(size(surface%element), 1)
        end associate
    end function mean_face
end module cfrd_contact_roles
