!> Consistent nodal forces of a normal pressure on a straight element face.
module cfrd_edge_load
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: face_pressure_forces

contains

    !> Pressure varying linearly from p1 at xa to p2 at xb on the face xa -> xb of an element
    !> numbered counter-clockwise; positive pressure pushes into the element, along the inward
    !> normal n = (-dy, dx)/L. With linear shape functions the consistent forces are exact:
    !> fa = L (2 p1 + p2)/6 n, fb = L (p1 + 2 p2)/6 n (docs/theory.md, "Loads").
    pure subroutine face_pressure_forces(xa, xb, p1, p2, fa, fb)
        real(dp), intent(in) :: xa(2), xb(2), p1, p2
        real(dp), intent(out) :: fa(2), fb(2)
        real(dp) :: n_times_length(2)
        n_times_length = [-(xb(2) - xa(2)), xb(1) - xa(1)]
        fa = (2.0_dp*p1 + p2)/6.0_dp*n_times_length
        fb = (p1 + 2.0_dp*p2)/6.0_dp*n_times_length
    end subroutine face_pressure_forces
end module cfrd_edge_load
