!> The 4-node isoparametric plane-strain quadrilateral with 2x2 Gauss integration
!> (docs/theory.md, section "The 4-node quadrilateral"). A 3-node triangle is the same element
!> with nodes 3 and 4 at one place: the Gauss points stay inside, where det J > 0.
module cfrd_quad4
    use cfrd_kinds, only: dp
    use cfrd_element, only: element_t
    use cfrd_shape, only: gauss_2x2, shape_fun, shape_der
    implicit none
    private

    public :: quad4_t, quad4_bmatrix

    integer, parameter :: nnode = 4, ngauss = 4, ncomp = 4, ndof = 8

    type, extends(element_t) :: quad4_t
    contains
        procedure, nopass :: nodes
        procedure, nopass :: gauss_points
        procedure, nopass :: components
        procedure, nopass :: stiffness
        procedure, nopass :: strains
        procedure, nopass :: internal_force
        procedure, nopass :: body_force
        procedure, nopass :: gauss_coordinates
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

    !> Strain-displacement matrix `bee` (4 x 8, rows xx, yy, zz, xy; the zz row is zero in
    !> plane strain) and the Jacobian determinant at (xi, eta).
    pure subroutine quad4_bmatrix(x, xi, eta, bee, det)
        real(dp), intent(in) :: x(:, :), xi, eta
        real(dp), intent(out) :: bee(ncomp, ndof), det
        real(dp) :: der(2, nnode), jac(2, 2), jinv(2, 2), deriv(2, nnode)
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
    end subroutine quad4_bmatrix

    pure subroutine stiffness(x, dmat, ke)
        real(dp), intent(in) :: x(:, :), dmat(:, :, :)
        real(dp), intent(out) :: ke(:, :)
        real(dp) :: points(2, ngauss), weights(ngauss), bee(ncomp, ndof), det, db(ncomp, ndof)
        integer :: ig
        call gauss_2x2(points, weights)
        ke(1:ndof, 1:ndof) = 0.0_dp
        do ig = 1, ngauss
            call quad4_bmatrix(x, points(1, ig), points(2, ig), bee, det)
            db = matmul(dmat(:, :, ig), bee)*(det*weights(ig))
            ke(1:ndof, 1:ndof) = ke(1:ndof, 1:ndof) + matmul(transpose(bee), db)
        end do
    end subroutine stiffness

    pure subroutine strains(x, u, strain)
        real(dp), intent(in) :: x(:, :), u(:)
        real(dp), intent(out) :: strain(:, :)
        real(dp) :: points(2, ngauss), weights(ngauss), bee(ncomp, ndof), det
        integer :: ig
        call gauss_2x2(points, weights)
        do ig = 1, ngauss
            call quad4_bmatrix(x, points(1, ig), points(2, ig), bee, det)
            strain(:, ig) = matmul(bee, u(1:ndof))
        end do
    end subroutine strains

    pure subroutine internal_force(x, stress, fe)
        real(dp), intent(in) :: x(:, :), stress(:, :)
        real(dp), intent(out) :: fe(:)
        real(dp) :: points(2, ngauss), weights(ngauss), bee(ncomp, ndof), det
        integer :: ig
        call gauss_2x2(points, weights)
        fe(1:ndof) = 0.0_dp
        do ig = 1, ngauss
            call quad4_bmatrix(x, points(1, ig), points(2, ig), bee, det)
            fe(1:ndof) = fe(1:ndof) + matmul(transpose(bee), stress(:, ig))*(det*weights(ig))
        end do
    end subroutine internal_force

    pure subroutine body_force(x, b, fe)
        real(dp), intent(in) :: x(:, :), b(2)
        real(dp), intent(out) :: fe(:)
        real(dp) :: points(2, ngauss), weights(ngauss), bee(ncomp, ndof), det, fun(nnode)
        integer :: ig, k
        call gauss_2x2(points, weights)
        fe(1:ndof) = 0.0_dp
        do ig = 1, ngauss
            call quad4_bmatrix(x, points(1, ig), points(2, ig), bee, det)
            fun = shape_fun(points(1, ig), points(2, ig))
            do k = 1, nnode
                fe(2*k - 1:2*k) = fe(2*k - 1:2*k) + fun(k)*b*(det*weights(ig))
            end do
        end do
    end subroutine body_force

    pure subroutine gauss_coordinates(x, xg)
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
