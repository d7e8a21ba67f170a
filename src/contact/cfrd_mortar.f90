!> Pure kernels of the contact discretisation on plain arrays (docs/theory.md section 14):
!> face normals, the segment-to-segment (mortar) integrals of one slave segment against one
!> master segment with dual Lagrange multipliers, and the node-to-segment projection.
module cfrd_mortar
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: face_normal, mortar_segment_pair, mortar_cell_points, project_node, dual_shape
    public :: closest_on_face
    public :: cross2

    !> 3-point Gauss rule on [-1, 1]: exact for the quadratic integrands of straight segments.
    real(dp), parameter :: gauss_xi(3) = [-0.77459666924148337704_dp, 0.0_dp, &
                                          0.77459666924148337704_dp]
    real(dp), parameter :: gauss_w(3) = [5.0_dp/9.0_dp, 8.0_dp/9.0_dp, 5.0_dp/9.0_dp]

contains

    !> z-component of the cross product of two plane vectors.
    pure real(dp) function cross2(a, b)
        real(dp), intent(in) :: a(2), b(2)
        cross2 = a(1)*b(2) - a(2)*b(1)
    end function cross2

    !> Outward unit normal of the face xa -> xb of a counter-clockwise element (the body
    !> lies on the left of the face): the unit tangent turned clockwise.
    pure function face_normal(xa, xb) result(n)
        real(dp), intent(in) :: xa(2), xb(2)
        real(dp) :: n(2), t(2)
        t = (xb - xa)/norm2(xb - xa)
        n = [t(2), -t(1)]
    end function face_normal

    !> Dual shape functions of a 2-node segment (Wohlmuth 2000): int Phi_j N_l = delta_jl
    !> int N_l, so the slave side's mortar matrix is diagonal on a fully supported segment.
    pure function dual_shape(xi) result(phi)
        real(dp), intent(in) :: xi
        real(dp) :: phi(2)
        phi = [0.5_dp*(1.0_dp - 3.0_dp*xi), 0.5_dp*(1.0_dp + 3.0_dp*xi)]
    end function dual_shape

    !> The integration points of the part of the slave segment xa -> xb that the master
    !> segment xc -> xd covers (between the projections of its ends along the slave segment's
    !> normal): slave coordinates xi(3), weights w(3) (ds included), and the coordinate eta(3)
    !> of the master point straight across each, on the straight master segment. `covered`
    !> is the length covered (0: none, the other outputs undefined).
    pure subroutine mortar_cell_points(xa, xb, xc, xd, xi, w, eta, covered)
        real(dp), intent(in) :: xa(2), xb(2), xc(2), xd(2)
        real(dp), intent(out) :: xi(3), w(3), eta(3), covered
        real(dp) :: t(2), length, xi_c, xi_d, lo, hi, x(2), denom
        integer :: ig
        covered = 0.0_dp
        xi = 0.0_dp
        w = 0.0_dp
        eta = 0.0_dp
        length = norm2(xb - xa)
        t = (xb - xa)/length
        denom = dot_product(xd - xc, t)
        ! A master segment square to the slave one covers nothing.
        if (abs(denom) <= 1.0e-12_dp*norm2(xd - xc)) return
        xi_c = 2.0_dp*dot_product(xc - xa, t)/length - 1.0_dp
        xi_d = 2.0_dp*dot_product(xd - xa, t)/length - 1.0_dp
        lo = max(-1.0_dp, min(xi_c, xi_d))
        hi = min(1.0_dp, max(xi_c, xi_d))
        if (hi - lo <= 1.0e-12_dp) return
        covered = 0.5_dp*(hi - lo)*length
        do ig = 1, size(gauss_xi)
            xi(ig) = 0.5_dp*(lo + hi) + 0.5_dp*(hi - lo)*gauss_xi(ig)
            x = 0.5_dp*(1.0_dp - xi(ig))*xa + 0.5_dp*(1.0_dp + xi(ig))*xb
            ! master coordinate of the point across: (x_m(eta) - x) . t = 0
            eta(ig) = 2.0_dp*dot_product(x - xc, t)/denom - 1.0_dp
            w(ig) = gauss_w(ig)*0.5_dp*(hi - lo)*0.5_dp*length
        end do
    end subroutine mortar_cell_points

    !> Mortar integrals of the slave segment xa -> xb against the master segment xc -> xd
    !> over the part of the slave segment that the master one covers, each point of the
    !> slave segment paired with the master point straight across it (along the slave
    !> segment's normal): d(j, l) = int Phi_j N_l ds (slave nodes j, l = a, b) and
    !> m(j, k) = int Phi_j N_k ds (master nodes k = c, d). `covered` is the length covered.
    pure subroutine mortar_segment_pair(xa, xb, xc, xd, d, m, covered)
        real(dp), intent(in) :: xa(2), xb(2), xc(2), xd(2)
        real(dp), intent(out) :: d(2, 2), m(2, 2), covered
        real(dp) :: xi(3), w(3), eta(3), phi(2)
        integer :: ig
        d = 0.0_dp
        m = 0.0_dp
        call mortar_cell_points(xa, xb, xc, xd, xi, w, eta, covered)
        if (covered <= 0.0_dp) return
        do ig = 1, 3
            phi = dual_shape(xi(ig))
            d(:, 1) = d(:, 1) + phi*0.5_dp*(1.0_dp - xi(ig))*w(ig)
            d(:, 2) = d(:, 2) + phi*0.5_dp*(1.0_dp + xi(ig))*w(ig)
            m(:, 1) = m(:, 1) + phi*0.5_dp*(1.0_dp - eta(ig))*w(ig)
            m(:, 2) = m(:, 2) + phi*0.5_dp*(1.0_dp + eta(ig))*w(ig)
        end do
    end subroutine mortar_segment_pair

    !> Node-to-segment: the point of the master segment xc -> xd straight across the slave
    !> node x along its normal n. `lambda` in [0, 1] locates it (N_c = 1 - lambda,
    !> N_d = lambda), `distance` is (x_m - x).n (the gap, + open); `hit` when it falls on
    !> the segment.
    pure subroutine project_node(x, n, xc, xd, lambda, distance, hit)
        real(dp), intent(in) :: x(2), n(2), xc(2), xd(2)
        real(dp), intent(out) :: lambda, distance
        logical, intent(out) :: hit
        real(dp) :: denom
        hit = .false.
        lambda = 0.0_dp
        distance = huge(1.0_dp)
        denom = cross2(xd - xc, n)
        if (abs(denom) <= 1.0e-12_dp*norm2(xd - xc)) return
        lambda = -cross2(xc - x, n)/denom
        if (lambda < -1.0e-12_dp .or. lambda > 1.0_dp + 1.0e-12_dp) return
        lambda = min(max(lambda, 0.0_dp), 1.0_dp)
        distance = dot_product(xc + lambda*(xd - xc) - x, n)
        hit = .true.
    end subroutine project_node

    !> The point of the face from a to b closest to p: `xi` locates p's projection on the
    !> face's line (a at 0, b at 1; not clamped: below 0 or above 1 p lies beyond an end),
    !> `distance` is |p - x(clamped xi)|.
    pure subroutine closest_on_face(p, a, b, xi, distance)
        real(dp), intent(in) :: p(2), a(2), b(2)
        real(dp), intent(out) :: xi, distance
        xi = dot_product(p - a, b - a)/max(dot_product(b - a, b - a), tiny(1.0_dp))
        distance = norm2(p - (a + min(1.0_dp, max(0.0_dp, xi))*(b - a)))
    end subroutine closest_on_face
end module cfrd_mortar
