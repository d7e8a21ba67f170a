!> In-plane principal stresses, used by the output and by the rockfill law.
module cfrd_principal
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: principal_stresses

contains

    !> For stress (xx, yy, zz, xy): sigma1 and sigma3, the algebraically largest and smallest
    !> in-plane principal stresses, and the angle of sigma1 from the x axis in degrees
    !> (counter-clockwise, in (-90, 90]).
    pure function principal_stresses(stress) result(p)
        real(dp), intent(in) :: stress(4)
        real(dp) :: p(3)
        real(dp) :: centre, radius
        real(dp), parameter :: deg = 57.295779513082320877_dp
        centre = 0.5_dp*(stress(1) + stress(2))
        radius = hypot(0.5_dp*(stress(1) - stress(2)), stress(4))
        p(1) = centre + radius
        p(2) = centre - radius
        if (radius > 0.0_dp) then
            p(3) = 0.5_dp*atan2(2.0_dp*stress(4), stress(1) - stress(2))*deg
        else
            p(3) = 0.0_dp
        end if
    end function principal_stresses
end module cfrd_principal
