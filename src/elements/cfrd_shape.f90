!> Shape functions and integration rules of the 4-node isoparametric quadrilateral,
!> in the vocabulary of Smith & Griffiths: `sample` (Gauss points and weights),
!> `shape_fun`, `shape_der`.
module cfrd_shape
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: gauss_2x2, shape_fun, shape_der, quad4_corner_xi, quad4_corner_eta

    !> Local coordinates of the corners, counter-clockwise from (-1,-1).
    real(dp), parameter :: quad4_corner_xi(4) = [-1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp]
    real(dp), parameter :: quad4_corner_eta(4) = [-1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp]

contains

    !> The 2x2 Gauss rule: points (xi, eta) = (+-1/sqrt 3, +-1/sqrt 3), weights 1, ordered
    !> like the corners so that point k is nearest to node k.
    pure subroutine gauss_2x2(points, weights)
        real(dp), intent(out) :: points(2, 4), weights(4)
        real(dp), parameter :: g = 0.57735026918962576451_dp
        points(1, :) = g*quad4_corner_xi
        points(2, :) = g*quad4_corner_eta
        weights = 1.0_dp
    end subroutine gauss_2x2

    !> Bilinear shape functions at (xi, eta).
    pure function shape_fun(xi, eta) result(fun)
        real(dp), intent(in) :: xi, eta
        real(dp) :: fun(4)
        fun = 0.25_dp*(1.0_dp + quad4_corner_xi*xi)*(1.0_dp + quad4_corner_eta*eta)
    end function shape_fun

    !> Derivatives of the shape functions: der(1,:) = dN/dxi, der(2,:) = dN/deta.
    pure function shape_der(xi, eta) result(der)
        real(dp), intent(in) :: xi, eta
        real(dp) :: der(2, 4)
        der(1, :) = 0.25_dp*quad4_corner_xi*(1.0_dp + quad4_corner_eta*eta)
        der(2, :) = 0.25_dp*quad4_corner_eta*(1.0_dp + quad4_corner_xi*xi)
    end function shape_der
end module cfrd_shape
