!> The Goodman joint: a 4-node zero-thickness interface element between two node pairs
!> (Goodman, Taylor & Brekke 1968; paper eq. 4; docs/theory.md section 12).
!> Nodes (counter-clockwise, like a quad of zero thickness): 1 and 2 on the bottom face
!> (cushion side), 3 above 2 and 4 above 1 (slab side). The local frame comes from the
!> bottom face: t = (x2 - x1) / L, n = (-t_y, t_x), so that n points to the top side.
!> "Strains" are the relative displacements of the top face over the bottom face at the
!> integration points, (du_n, du_s) = T N u (opening and slip positive along n and t);
!> "stresses" are the tractions (sigma_n, tau), tension positive.
!> Integration: 2-point Gauss (xi = +-1/sqrt 3) or 2-point Newton-Cotes / Lobatto
!> (xi = +-1, i.e. nodal lumping), chosen per element kind.
module cfrd_joint4
    use cfrd_kinds, only: dp
    use cfrd_element, only: element_t, element_geometry_t
    implicit none
    private

    public :: joint4_t, joint_frame

    integer, parameter :: nnode = 4, ngauss = 2, ncomp = 2, ndof = 8

    type, extends(element_t) :: joint4_t
        logical :: lobatto = .false.       !! Newton-Cotes (nodal) rule instead of Gauss
        logical :: axisymmetric = .false.
    contains
        procedure, nopass :: nodes
        procedure, nopass :: gauss_points
        procedure, nopass :: components
        procedure :: geometry
        procedure :: stiffness_geo
        procedure :: strains_geo
        procedure :: internal_force_geo
        procedure :: body_force
        procedure :: face_pressure
        procedure :: gauss_coordinates
    end type joint4_t

contains

    pure integer function nodes()
        nodes = nnode
    end function nodes

    pure integer function gauss_points()
        gauss_points = ngauss
    end function gauss_points

    pure integer function components()
        components = ncomp
    end function components

    !> Unit tangent t and normal n of the joint and its length, from the bottom face.
    pure subroutine joint_frame(x, t, n, length)
        real(dp), intent(in) :: x(:, :)
        real(dp), intent(out) :: t(2), n(2), length
        t = x(:, 2) - x(:, 1)
        length = norm2(t)
        t = t/length
        n = [-t(2), t(1)]
    end subroutine joint_frame

    !> Integration points xi and weights of the element's rule on [-1, 1].
    pure subroutine rule(self, xi, w)
        class(joint4_t), intent(in) :: self
        real(dp), intent(out) :: xi(ngauss), w(ngauss)
        real(dp), parameter :: g = 0.57735026918962576451_dp
        if (self%lobatto) then
            xi = [-1.0_dp, 1.0_dp]
        else
            xi = [-g, g]
        end if
        w = 1.0_dp
    end subroutine rule

    !> B (2 x 8): rows (n, t) of the relative displacement at xi, and the weight dS of
    !> the point (L/2, times the radius when axisymmetric).
    pure subroutine joint_bmatrix(self, x, xi, bee, ds)
        class(joint4_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :), xi
        real(dp), intent(out) :: bee(ncomp, ndof), ds
        real(dp) :: t(2), n(2), length, fun(nnode)
        integer :: k
        call joint_frame(x, t, n, length)
        ! Bottom nodes 1, 2 count negative, top nodes 4 (over 1) and 3 (over 2) positive.
        fun = 0.5_dp*[-(1.0_dp - xi), -(1.0_dp + xi), 1.0_dp + xi, 1.0_dp - xi]
        do k = 1, nnode
            bee(1, 2*k - 1:2*k) = fun(k)*n
            bee(2, 2*k - 1:2*k) = fun(k)*t
        end do
        ds = 0.5_dp*length
        if (self%axisymmetric) ds = ds*0.5_dp*((1.0_dp - xi)*x(1, 1) + (1.0_dp + xi)*x(1, 2))
    end subroutine joint_bmatrix

    !> B (rows 1:2) and dS at the integration points, computed once per element.
    pure subroutine geometry(self, x, geo)
        class(joint4_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :)
        type(element_geometry_t), intent(out) :: geo
        real(dp) :: xi(ngauss), w(ngauss), bee(ncomp, ndof)
        integer :: ig
        call rule(self, xi, w)
        do ig = 1, ngauss
            call joint_bmatrix(self, x, xi(ig), bee, geo%dv(ig))
            geo%bee(1:ncomp, 1:ndof, ig) = bee
        end do
    end subroutine geometry

    pure subroutine stiffness_geo(self, geo, dmat, ke)
        class(joint4_t), intent(in) :: self
        type(element_geometry_t), intent(in) :: geo
        real(dp), intent(in) :: dmat(:, :, :)
        real(dp), intent(out) :: ke(:, :)
        real(dp) :: xi(ngauss), w(ngauss), bee(ncomp, ndof), ds
        integer :: ig
        call rule(self, xi, w)
        ke(1:ndof, 1:ndof) = 0.0_dp
        do ig = 1, ngauss
            bee = geo%bee(1:ncomp, 1:ndof, ig)
            ds = geo%dv(ig)
            ke(1:ndof, 1:ndof) = ke(1:ndof, 1:ndof) + &
                matmul(transpose(bee), matmul(dmat(1:ncomp, 1:ncomp, ig), bee))*(ds*w(ig))
        end do
    end subroutine stiffness_geo

    pure subroutine strains_geo(self, geo, u, strain)
        class(joint4_t), intent(in) :: self
        type(element_geometry_t), intent(in) :: geo
        real(dp), intent(in) :: u(:)
        real(dp), intent(out) :: strain(:, :)
        real(dp) :: bee(ncomp, ndof)
        integer :: ig
        strain = 0.0_dp
        do ig = 1, ngauss
            bee = geo%bee(1:ncomp, 1:ndof, ig)
            strain(1:ncomp, ig) = matmul(bee, u(1:ndof))
        end do
    end subroutine strains_geo

    pure subroutine internal_force_geo(self, geo, stress, fe)
        class(joint4_t), intent(in) :: self
        type(element_geometry_t), intent(in) :: geo
        real(dp), intent(in) :: stress(:, :)
        real(dp), intent(out) :: fe(:)
        real(dp) :: xi(ngauss), w(ngauss), bee(ncomp, ndof), ds
        integer :: ig
        call rule(self, xi, w)
        fe(1:ndof) = 0.0_dp
        do ig = 1, ngauss
            bee = geo%bee(1:ncomp, 1:ndof, ig)
            ds = geo%dv(ig)
            fe(1:ndof) = fe(1:ndof) + matmul(transpose(bee), stress(1:ncomp, ig))*(ds*w(ig))
        end do
    end subroutine internal_force_geo

    !> A zero-thickness joint has no volume, hence no weight.
    pure subroutine body_force(self, x, b, fe)
        class(joint4_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :), b(2)
        real(dp), intent(out) :: fe(:)
        fe(1:ndof) = 0.0_dp
    end subroutine body_force

    !> Faces of a joint are never loaded (the deck reader refuses them); zero forces.
    pure subroutine face_pressure(self, xa, xb, p1, p2, fa, fb)
        class(joint4_t), intent(in) :: self
        real(dp), intent(in) :: xa(2), xb(2), p1, p2
        real(dp), intent(out) :: fa(2), fb(2)
        fa = 0.0_dp
        fb = 0.0_dp
    end subroutine face_pressure

    pure subroutine gauss_coordinates(self, x, xg)
        class(joint4_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :)
        real(dp), intent(out) :: xg(:, :)
        real(dp) :: xi(ngauss), w(ngauss)
        integer :: ig
        call rule(self, xi, w)
        do ig = 1, ngauss
            xg(:, ig) = 0.5_dp*((1.0_dp - xi(ig))*x(:, 1) + (1.0_dp + xi(ig))*x(:, 2))
        end do
    end subroutine gauss_coordinates
end module cfrd_joint4
