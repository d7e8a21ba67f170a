!> The perimetric-joint law (PJOINT; docs/theory.md section 12) of the zero-thickness
!> joint between the face slab and the plinth, as pure functions. Tractions (sigma_n, tau)
!> and relative displacements (du_n, du_s) of the joint's frame, tension and opening
!> positive, as for the Goodman law:
!>
!> - Normal: sigma_n = knc du_n while the joint is closed (du_n <= 0), the concrete faces
!>   pressed together; knt du_n when it opens, the waterstops (copper and PVC) alone
!>   holding the slab to the plinth, so knt << knc.
!> - Shear: tau = ks du_s, linear in the total slip, open or closed (the waterstops carry
!>   the shear of an open joint; a closed joint's filler has no friction limit here).
!>
!> The law is elastic and bilinear: the tractions depend on the total relative
!> displacements only, and the update over an increment is exact.
module cfrd_pjoint
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: pjoint_params_t, pjoint_stress, pjoint_tangent

    type :: pjoint_params_t
        real(dp) :: kn_compression = 0.0_dp   !! kPa/m, closed joint
        real(dp) :: kn_tension = 0.0_dp       !! kPa/m, open joint (waterstops)
        real(dp) :: ks = 0.0_dp               !! kPa/m, shear
    end type pjoint_params_t

contains

    !> Tractions (sigma_n, tau) at the total relative displacements e = (du_n, du_s).
    pure function pjoint_stress(p, e) result(s)
        type(pjoint_params_t), intent(in) :: p
        real(dp), intent(in) :: e(2)
        real(dp) :: s(2)
        real(dp) :: d(2, 2)
        call pjoint_tangent(p, e, d)
        s = [d(1, 1)*e(1), d(2, 2)*e(2)]
    end function pjoint_stress

    !> Tangent d(2,2) = diag(kn, ks) at e: kn = knc closed (du_n <= 0), knt open.
    pure subroutine pjoint_tangent(p, e, d)
        type(pjoint_params_t), intent(in) :: p
        real(dp), intent(in) :: e(2)
        real(dp), intent(out) :: d(2, 2)
        d = 0.0_dp
        d(1, 1) = merge(p%kn_tension, p%kn_compression, e(1) > 0.0_dp)
        d(2, 2) = p%ks
    end subroutine pjoint_tangent
end module cfrd_pjoint
