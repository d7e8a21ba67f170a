!> Linear isotropic elasticity, plane strain, as a `pure` law.
!> Components are ordered (xx, yy, zz, xy) with the engineering shear strain gamma_xy;
!> the zz row carries the out-of-plane stress sigma_zz = nu (sigma_xx + sigma_yy) of plane
!> strain (docs/theory.md, section "Linear elasticity").
module cfrd_elastic
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: elastic_dmatrix, constrained_modulus

contains

    !> The 4x4 elasticity matrix D, sigma = D eps, for Young's modulus `e` and Poisson's ratio
    !> `nu` (0 <= nu < 0.5, checked by the deck reader).
    pure function elastic_dmatrix(e, nu) result(d)
        real(dp), intent(in) :: e, nu
        real(dp) :: d(4, 4)
        real(dp) :: c
        c = e/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu))
        d = 0.0_dp
        d(1:3, 1:3) = c*nu
        d(1, 1) = c*(1.0_dp - nu)
        d(2, 2) = c*(1.0_dp - nu)
        d(3, 3) = c*(1.0_dp - nu)
        d(4, 4) = c*(1.0_dp - 2.0_dp*nu)/2.0_dp
    end function elastic_dmatrix

    !> Oedometric (constrained) modulus M = E (1 - nu) / ((1 + nu)(1 - 2 nu)).
    pure real(dp) function constrained_modulus(e, nu)
        real(dp), intent(in) :: e, nu
        constrained_modulus = e*(1.0_dp - nu)/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu))
    end function constrained_modulus
end module cfrd_elastic
