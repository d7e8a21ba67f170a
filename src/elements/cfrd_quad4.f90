!> The 4-node isoparametric quadrilateral with 2x2 Gauss integration, plane strain or
!> axisymmetric (docs/theory.md, sections 3 and 10). A 3-node triangle is the same element
!> with nodes 3 and 4 at one place: the Gauss points stay inside, where det J > 0.
!> Axisymmetric: x is the radius r, y the axis z; the zz component is the hoop strain u_r / r
!> and every integral is per radian (dV = r dA).
!> With `assumed_shear` (element type Q4S) the natural shear strain is taken at the element's
!> centre at every Gauss point (an assumed shear strain, docs/theory.md section 3): a slender
!> element in bending no longer locks in parasitic shear (the face slab).
module cfrd_quad4
    use cfrd_kinds, only: dp
    use cfrd_element, only: element_t, element_geometry_t
    use cfrd_shape, only: gauss_2x2, shape_fun, shape_der
    use cfrd_edge_load, only: face_pressure_forces
    implicit none
    private

    public :: quad4_t, quad4_bmatrix

    integer, parameter :: nnode = 4, ngauss = 4, ncomp = 4, ndof = 8

    type, extends(element_t) :: quad4_t
        logical :: axisymmetric = .false.
        logical :: assumed_shear = .false.   !! Q4S: natural shear strain from the centre
    contains
        procedure, nopass :: nodes
        procedure, nopass :: gauss_points
        procedure, nopass :: components
        procedure :: element_bmatrix
        procedure :: geometry
        procedure :: stiffness_geo
        procedure :: strains_geo
        procedure :: internal_force_geo
        procedure :: body_force
        procedure :: face_pressure
        procedure :: gauss_coordinates
    end type quad4_t

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

    !> Strain-displacement matrix `bee` (4 x 8, rows xx, yy, zz, xy) and the volume weight
    !> dv = det J (plane strain, unit thickness) or r det J (axisymmetric, per radian) at
    !> (xi, eta). In plane strain the zz row is zero; axisymmetric it is N_i / r (hoop strain).
    pure subroutine quad4_bmatrix(x, xi, eta, axisymmetric, bee, dv)
        real(dp), intent(in) :: x(:, :), xi, eta
        logical, intent(in) :: axisymmetric
        real(dp), intent(out) :: bee(ncomp, ndof), dv
        real(dp) :: der(2, nnode), jac(2, 2), jinv(2, 2), deriv(2, nnode), det, fun(nnode), r
        integer :: k
        der = shape_der(xi, eta)
        jac = matmul(der, transpose(x(:, 1:nnode)))   ! jac(i,j) = d x_j / d xi_i
        det = jac(1, 1)*jac(2, 2) - jac(1, 2)*jac(2, 1)
        jinv(1, 1) = jac(2, 2)/det
        jinv(2, 2) = jac(1, 1)/det
        jinv(1, 2) = -jac(1, 2)/det
        jinv(2, 1) = -jac(2, 1)/det
        deriv = matmul(jinv, der)                      ! d N / d(x, y)
        bee = 0.0_dp
        do k = 1, nnode
            bee(1, 2*k - 1) = deriv(1, k)
            bee(2, 2*k) = deriv(2, k)
            bee(4, 2*k - 1) = deriv(2, k)
            bee(4, 2*k) = deriv(1, k)
        end do
        dv = det
        if (axisymmetric) then
            fun = shape_fun(xi, eta)
            r = dot_product(fun, x(1, 1:nnode))
            bee(3, 1:ndof:2) = fun/r
            dv = det*r
        end if
    end subroutine quad4_bmatrix

    !> The strain-displacement matrix of the element at (xi, eta): the standard one, or (Q4S)
    !> with the natural shear strain of the centre: at each point the strain is written in
    !> the natural components of the centre, E = J0 eps J0^T (J0 the Jacobian at the centre),
    !> E_xi_eta is replaced by its value at the centre, and eps = J0^-1 E J0^-T. A uniform
    !> strain keeps its value everywhere (the patch test, any shape); on a parallelogram the
    !> linear E_xi_eta of bending (parasitic shear) is gone. Triangles (nodes 3 and 4 at one
    !> place) keep the standard matrix.
    pure subroutine element_bmatrix(self, x, xi, eta, bee, dv)
        class(quad4_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :), xi, eta
        real(dp), intent(out) :: bee(ncomp, ndof), dv
        real(dp) :: b0(ncomp, ndof), dv0, jac0(2, 2), jinv0(2, 2), e(2, 2), e0(2, 2)
        integer :: k
        call quad4_bmatrix(x, xi, eta, self%axisymmetric, bee, dv)
        if (.not. self%assumed_shear) return
        if (all(x(:, 3) == x(:, 4))) return
        call quad4_bmatrix(x, 0.0_dp, 0.0_dp, self%axisymmetric, b0, dv0)
        jac0 = matmul(shape_der(0.0_dp, 0.0_dp), transpose(x(:, 1:nnode)))
        jinv0 = reshape([jac0(2, 2), -jac0(2, 1), -jac0(1, 2), jac0(1, 1)], [2, 2])/ &
                (jac0(1, 1)*jac0(2, 2) - jac0(1, 2)*jac0(2, 1))
        do k = 1, ndof
            e = matmul(jac0, matmul(tensor(bee(:, k)), transpose(jac0)))
            e0 = matmul(jac0, matmul(tensor(b0(:, k)), transpose(jac0)))
            e(1, 2) = e0(1, 2)
            e(2, 1) = e0(1, 2)
            e = matmul(jinv0, matmul(e, transpose(jinv0)))
            bee(1, k) = e(1, 1)
            bee(2, k) = e(2, 2)
            bee(4, k) = 2.0_dp*e(1, 2)
        end do
    contains
        !> In-plane strain tensor of (xx, yy, zz, xy engineering) components.
        pure function tensor(col) result(t)
            real(dp), intent(in) :: col(ncomp)
            real(dp) :: t(2, 2)
            t = reshape([col(1), 0.5_dp*col(4), 0.5_dp*col(4), col(2)], [2, 2])
        end function tensor
    end subroutine element_bmatrix

    !> B and dV at the 2x2 Gauss points (element_bmatrix), computed once per element.
    pure subroutine geometry(self, x, geo)
        class(quad4_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :)
        type(element_geometry_t), intent(out) :: geo
        real(dp) :: points(2, ngauss), weights(ngauss)
        integer :: ig
        call gauss_2x2(points, weights)
        do ig = 1, ngauss
            call self%element_bmatrix(x, points(1, ig), points(2, ig), geo%bee(:, :, ig), &
                                      geo%dv(ig))
        end do
    end subroutine geometry

    !> ke = sum over points of B^T (D B dV w). A standard quad's B has, for node k, the
    !> columns (N_k,x, 0, h_k, N_k,y) and (0, N_k,y, 0, N_k,x) (h_k = N_k / r axisymmetric,
    !> else 0): the products are taken over those entries only, in the order of the full
    !> product (terms in B's zeros add exact zeros). Q4S's B is full: the full product.
    pure subroutine stiffness_geo(self, geo, dmat, ke)
        class(quad4_t), intent(in) :: self
        type(element_geometry_t), intent(in) :: geo
        real(dp), intent(in) :: dmat(:, :, :)
        real(dp), intent(out) :: ke(:, :)
        real(dp) :: points(2, ngauss), weights(ngauss), db(ncomp, ndof), s, t
        real(dp) :: nx(nnode), ny(nnode), h(nnode)
        integer :: ig, i, j, k
        call gauss_2x2(points, weights)
        ke(1:ndof, 1:ndof) = 0.0_dp
        do ig = 1, ngauss
            associate (bee => geo%bee(:, :, ig), d => dmat(:, :, ig))
                if (self%assumed_shear) then
                    db = matmul(d, bee)*(geo%dv(ig)*weights(ig))
                    ke(1:ndof, 1:ndof) = ke(1:ndof, 1:ndof) + matmul(transpose(bee), db)
                    cycle
                end if
                s = geo%dv(ig)*weights(ig)
                nx = bee(1, 1:ndof:2)
                ny = bee(2, 2:ndof:2)
                h = bee(3, 1:ndof:2)
                ! Each sum from zero, term by term, as the full product takes it.
                do k = 1, nnode
                    do i = 1, ncomp
                        t = 0.0_dp
                        t = t + d(i, 1)*nx(k)
                        t = t + d(i, 3)*h(k)
                        t = t + d(i, 4)*ny(k)
                        db(i, 2*k - 1) = t*s
                        t = 0.0_dp
                        t = t + d(i, 2)*ny(k)
                        t = t + d(i, 4)*nx(k)
                        db(i, 2*k) = t*s
                    end do
                end do
                do j = 1, ndof
                    do k = 1, nnode
                        t = 0.0_dp
                        t = t + nx(k)*db(1, j)
                        t = t + h(k)*db(3, j)
                        t = t + ny(k)*db(4, j)
                        ke(2*k - 1, j) = ke(2*k - 1, j) + t
                        t = 0.0_dp
                        t = t + ny(k)*db(2, j)
                        t = t + nx(k)*db(4, j)
                        ke(2*k, j) = ke(2*k, j) + t
                    end do
                end do
            end associate
        end do
    end subroutine stiffness_geo

    !> strain = B u at each point; a standard quad over B's nonzero entries (stiffness_geo),
    !> each sum from zero in the order of the full product; Q4S the full product.
    pure subroutine strains_geo(self, geo, u, strain)
        class(quad4_t), intent(in) :: self
        type(element_geometry_t), intent(in) :: geo
        real(dp), intent(in) :: u(:)
        real(dp), intent(out) :: strain(:, :)
        real(dp) :: txx, tyy, tzz, txy
        integer :: ig, k
        do ig = 1, ngauss
            associate (bee => geo%bee(:, :, ig))
                if (self%assumed_shear) then
                    strain(:, ig) = matmul(bee, u(1:ndof))
                    cycle
                end if
                txx = 0.0_dp
                tyy = 0.0_dp
                tzz = 0.0_dp
                txy = 0.0_dp
                do k = 1, nnode
                    txx = txx + bee(1, 2*k - 1)*u(2*k - 1)
                    tyy = tyy + bee(2, 2*k)*u(2*k)
                    tzz = tzz + bee(3, 2*k - 1)*u(2*k - 1)
                    txy = txy + bee(4, 2*k - 1)*u(2*k - 1)
                    txy = txy + bee(4, 2*k)*u(2*k)
                end do
                strain(1:ncomp, ig) = [txx, tyy, tzz, txy]
            end associate
        end do
    end subroutine strains_geo

    pure subroutine internal_force_geo(self, geo, stress, fe)
        class(quad4_t), intent(in) :: self
        type(element_geometry_t), intent(in) :: geo
        real(dp), intent(in) :: stress(:, :)
        real(dp), intent(out) :: fe(:)
        real(dp) :: points(2, ngauss), weights(ngauss)
        integer :: ig
        call gauss_2x2(points, weights)
        fe(1:ndof) = 0.0_dp
        do ig = 1, ngauss
            fe(1:ndof) = fe(1:ndof) + matmul(transpose(geo%bee(:, :, ig)), stress(:, ig))* &
                         (geo%dv(ig)*weights(ig))
        end do
    end subroutine internal_force_geo

    pure subroutine body_force(self, x, b, fe)
        class(quad4_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :), b(2)
        real(dp), intent(out) :: fe(:)
        real(dp) :: points(2, ngauss), weights(ngauss), bee(ncomp, ndof), dv, fun(nnode)
        integer :: ig, k
        call gauss_2x2(points, weights)
        fe(1:ndof) = 0.0_dp
        do ig = 1, ngauss
            call quad4_bmatrix(x, points(1, ig), points(2, ig), self%axisymmetric, bee, dv)
            fun = shape_fun(points(1, ig), points(2, ig))
            do k = 1, nnode
                fe(2*k - 1:2*k) = fe(2*k - 1:2*k) + fun(k)*b*(dv*weights(ig))
            end do
        end do
    end subroutine body_force

    !> Plane strain: the closed form of cfrd_edge_load. Axisymmetric: the traction p n r is
    !> cubic along the face (p and r linear), so 2-point Gauss on the face is exact.
    pure subroutine face_pressure(self, xa, xb, p1, p2, fa, fb)
        class(quad4_t), intent(in) :: self
        real(dp), intent(in) :: xa(2), xb(2), p1, p2
        real(dp), intent(out) :: fa(2), fb(2)
        real(dp), parameter :: g = 0.57735026918962576451_dp
        real(dp) :: n_times_length(2), s, na, nb, p, r
        integer :: k
        if (.not. self%axisymmetric) then
            call face_pressure_forces(xa, xb, p1, p2, fa, fb)
            return
        end if
        n_times_length = [-(xb(2) - xa(2)), xb(1) - xa(1)]
        fa = 0.0_dp
        fb = 0.0_dp
        do k = 1, 2
            s = 0.5_dp*(1.0_dp + merge(-g, g, k == 1))   ! position along the face, 0..1
            na = 1.0_dp - s
            nb = s
            p = na*p1 + nb*p2
            r = na*xa(1) + nb*xb(1)
            ! Weight 1/2 per point maps the length-1 interval; n_times_length carries L.
            fa = fa + 0.5_dp*na*p*r*n_times_length
            fb = fb + 0.5_dp*nb*p*r*n_times_length
        end do
    end subroutine face_pressure

    pure subroutine gauss_coordinates(self, x, xg)
        class(quad4_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :)
        real(dp), intent(out) :: xg(:, :)
        real(dp) :: points(2, ngauss), weights(ngauss)
        integer :: ig
        call gauss_2x2(points, weights)
        do ig = 1, ngauss
            xg(:, ig) = matmul(x(:, 1:nnode), shape_fun(points(1, ig), points(2, ig)))
        end do
    end subroutine gauss_coordinates
end module cfrd_quad4
