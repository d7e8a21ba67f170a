!> Tests of the element geometry computed once (issue 21): the B matrices and volume weights
!> an element stores in its element_geometry_t, against the shape-function derivatives worked
!> out by hand for a parallelogram (closed form: a constant Jacobian), against the joint's
!> frame by hand, and against B recomputed from the coordinates for a distorted quad; and the
!> per-element records of make_elements against the same.
module test_elements_geometry
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_element, only: element_geometry_t
    use cfrd_quad4, only: quad4_t
    use cfrd_joint4, only: joint4_t
    use cfrd_shape, only: gauss_2x2, shape_fun, quad4_corner_xi, quad4_corner_eta
    use cfrd_model, only: model_t, elem_quad4, elem_joint_gauss
    use cfrd_assembly, only: element_box_t, make_elements
    implicit none
    private

    public :: collect_elements_geometry

    !> The parallelogram (0,0), (a,0), (a+c,b), (c,b).
    real(dp), parameter :: a = 2.0_dp, b = 1.5_dp, c = 0.6_dp, x0 = 3.0_dp
    !> A distorted quad (counter-clockwise): no closed form, B recomputed from x instead.
    real(dp), parameter :: x_distorted(2, 4) = reshape([0.0_dp, 0.0_dp, 2.0_dp, 0.3_dp, &
                                                        2.4_dp, 1.7_dp, -0.2_dp, 1.1_dp], [2, 4])
    !> Round-off of the hand formulas against the isoparametric map [choice: 1e-14 relative
    !> to the largest entry, some hundred ulps].
    real(dp), parameter :: tol = 1.0e-14_dp
    real(dp), parameter :: g = 0.57735026918962576451_dp

contains

    subroutine collect_elements_geometry(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('parallelogram_b_by_hand', test_parallelogram), &
                new_unittest('axisymmetric_parallelogram_by_hand', test_axisymmetric), &
                new_unittest('q4s_rectangle_shear_from_centre', test_q4s_rectangle), &
                new_unittest('distorted_quad_and_q4s_as_recomputed', test_distorted), &
                new_unittest('joint_frame_by_hand', test_joint), &
                new_unittest('make_elements_records', test_library), &
                new_unittest('stiffness_kernel_full_product', test_kernel), &
                new_unittest('strains_kernel_full_product', test_strains_kernel) &
                ]
    end subroutine collect_elements_geometry

    !> The parallelogram's corners, shifted by x0 in x (positive radii when axisymmetric).
    pure function parallelogram() result(x)
        real(dp) :: x(2, 4)
        x = reshape([x0, 0.0_dp, x0 + a, 0.0_dp, x0 + a + c, b, x0 + c, b], [2, 4])
    end function parallelogram

    !> By hand: on the parallelogram x = x0 + a (xi+1)/2 + c (eta+1)/2, y = b (eta+1)/2, so
    !> xi,x = 2/a, xi,y = -2c/(ab), eta,x = 0, eta,y = 2/b; with dN_k/dxi = xi_k (1 + eta_k
    !> eta)/4 and dN_k/deta = eta_k (1 + xi_k xi)/4: N_k,x = 2/a N_k,xi and N_k,y =
    !> -2c/(ab) N_k,xi + 2/b N_k,eta. det J = ab/4. Rows xx, yy, zz (zero), xy.
    pure subroutine b_by_hand(xi, eta, bee, det)
        real(dp), intent(in) :: xi, eta
        real(dp), intent(out) :: bee(4, 8), det
        real(dp) :: n_xi, n_eta, n_x, n_y
        integer :: k
        bee = 0.0_dp
        do k = 1, 4
            n_xi = quad4_corner_xi(k)*(1.0_dp + quad4_corner_eta(k)*eta)/4.0_dp
            n_eta = quad4_corner_eta(k)*(1.0_dp + quad4_corner_xi(k)*xi)/4.0_dp
            n_x = 2.0_dp/a*n_xi
            n_y = -2.0_dp*c/(a*b)*n_xi + 2.0_dp/b*n_eta
            bee(1, 2*k - 1) = n_x
            bee(2, 2*k) = n_y
            bee(4, 2*k - 1) = n_y
            bee(4, 2*k) = n_x
        end do
        det = a*b/4.0_dp
    end subroutine b_by_hand

    !> Every entry of `actual` against `expected`, within tol of the largest |expected|.
    subroutine check_matrix(error, actual, expected, what)
        type(error_t), allocatable, intent(out) :: error
        real(dp), intent(in) :: actual(:, :), expected(:, :)
        character(len=*), intent(in) :: what
        integer :: i, j
        do j = 1, size(expected, 2)
            do i = 1, size(expected, 1)
                call check(error, actual(i, j), expected(i, j), what, &
                           abs=tol*maxval(abs(expected)))
                if (allocated(error)) return
            end do
        end do
    end subroutine check_matrix

    !> Plane strain: the cached B and dV of the parallelogram = the hand formulas.
    subroutine test_parallelogram(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quad
        type(element_geometry_t) :: geo
        real(dp) :: points(2, 4), weights(4), bee(4, 8), det
        integer :: ig
        call quad%geometry(parallelogram(), geo)
        call gauss_2x2(points, weights)
        do ig = 1, 4
            call b_by_hand(points(1, ig), points(2, ig), bee, det)
            call check_matrix(error, geo%bee(:, :, ig), bee, 'B by hand (parallelogram)')
            if (allocated(error)) return
            call check(error, geo%dv(ig), det, 'dV = ab/4', rel=tol)
            if (allocated(error)) return
        end do
    end subroutine test_parallelogram

    !> Axisymmetric: rows xx, yy, xy as in plane strain, the hoop row N_k / r with r =
    !> x0 + a (xi+1)/2 + c (eta+1)/2, and dV = r ab/4 (per radian).
    subroutine test_axisymmetric(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quad
        type(element_geometry_t) :: geo
        real(dp) :: points(2, 4), weights(4), bee(4, 8), det, r, fun(4)
        integer :: ig
        quad = quad4_t(axisymmetric=.true.)
        call quad%geometry(parallelogram(), geo)
        call gauss_2x2(points, weights)
        do ig = 1, 4
            call b_by_hand(points(1, ig), points(2, ig), bee, det)
            r = x0 + a*(points(1, ig) + 1.0_dp)/2.0_dp + c*(points(2, ig) + 1.0_dp)/2.0_dp
            fun = (1.0_dp + quad4_corner_xi*points(1, ig))* &
                  (1.0_dp + quad4_corner_eta*points(2, ig))/4.0_dp
            bee(3, 1:8:2) = fun/r
            call check_matrix(error, geo%bee(:, :, ig), bee, 'axisymmetric B by hand')
            if (allocated(error)) return
            call check(error, geo%dv(ig), det*r, 'dV = r ab/4', rel=tol)
            if (allocated(error)) return
        end do
    end subroutine test_axisymmetric

    !> Q4S on a rectangle (c = 0: J diagonal, so the natural and the Cartesian shear are
    !> proportional): rows xx and yy as at the point, the shear row that of the centre
    !> (docs/theory.md section 3), by hand.
    subroutine test_q4s_rectangle(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quad
        type(element_geometry_t) :: geo
        real(dp) :: points(2, 4), weights(4), bee(4, 8), centre(4, 8), det, x(2, 4)
        integer :: ig, k
        quad = quad4_t(assumed_shear=.true.)
        x = reshape([0.0_dp, 0.0_dp, a, 0.0_dp, a, b, 0.0_dp, b], [2, 4])
        call quad%geometry(x, geo)
        call gauss_2x2(points, weights)
        do ig = 1, 4
            bee = 0.0_dp
            centre = 0.0_dp
            do k = 1, 4
                ! On the rectangle N_k,x = 2/a N_k,xi and N_k,y = 2/b N_k,eta.
                bee(1, 2*k - 1) = 2.0_dp/a*quad4_corner_xi(k)* &
                                  (1.0_dp + quad4_corner_eta(k)*points(2, ig))/4.0_dp
                bee(2, 2*k) = 2.0_dp/b*quad4_corner_eta(k)* &
                              (1.0_dp + quad4_corner_xi(k)*points(1, ig))/4.0_dp
                centre(4, 2*k - 1) = 2.0_dp/b*quad4_corner_eta(k)/4.0_dp
                centre(4, 2*k) = 2.0_dp/a*quad4_corner_xi(k)/4.0_dp
            end do
            bee(4, :) = centre(4, :)
            call check_matrix(error, geo%bee(:, :, ig), bee, 'Q4S B by hand (rectangle)')
            if (allocated(error)) return
            det = a*b/4.0_dp
            call check(error, geo%dv(ig), det, 'dV = ab/4 (Q4S)', rel=tol)
            if (allocated(error)) return
        end do
    end subroutine test_q4s_rectangle

    !> A distorted quad, standard and Q4S, plane strain and axisymmetric: the cached B and dV
    !> are, bit for bit, those element_bmatrix computes from the coordinates at the point.
    subroutine test_distorted(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quads(4)
        type(element_geometry_t) :: geo
        real(dp) :: points(2, 4), weights(4), bee(4, 8), dv, x(2, 4)
        integer :: ig, q
        quads = [quad4_t(), quad4_t(assumed_shear=.true.), quad4_t(axisymmetric=.true.), &
                 quad4_t(axisymmetric=.true., assumed_shear=.true.)]
        x = x_distorted
        x(1, :) = x(1, :) + 1.0_dp   ! positive radii
        call gauss_2x2(points, weights)
        do q = 1, size(quads)
            call quads(q)%geometry(x, geo)
            do ig = 1, 4
                call quads(q)%element_bmatrix(x, points(1, ig), points(2, ig), bee, dv)
                call check(error, all(geo%bee(:, :, ig) == bee) .and. geo%dv(ig) == dv, &
                           'cached B, dV = recomputed from x (bit for bit)')
                if (allocated(error)) return
            end do
        end do
    end subroutine test_distorted

    !> A joint along angle theta, length L, from x1: by hand t = (cos, sin), n = (-sin, cos),
    !> B rows (n, t) times the relative-displacement weights -(1-xi)/2, -(1+xi)/2, (1+xi)/2,
    !> (1-xi)/2 of nodes 1..4, dS = L/2 (times r(xi) axisymmetric), at xi = -+1/sqrt 3 (Gauss)
    !> or -+1 (Lobatto).
    subroutine test_joint(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: theta = 0.7_dp, length = 2.5_dp, x1(2) = [1.2_dp, -0.4_dp]
        type(joint4_t) :: joints(3)
        type(element_geometry_t) :: geo
        real(dp) :: x(2, 4), t(2), n(2), xis(2), bee(2, 8), fun(4), ds, r
        integer :: j, ig, k
        joints = [joint4_t(), joint4_t(lobatto=.true.), joint4_t(axisymmetric=.true.)]
        t = [cos(theta), sin(theta)]
        n = [-sin(theta), cos(theta)]
        x(:, 1) = x1
        x(:, 2) = x1 + length*t
        x(:, 3) = x(:, 2)
        x(:, 4) = x(:, 1)
        do j = 1, size(joints)
            call joints(j)%geometry(x, geo)
            xis = merge([-1.0_dp, 1.0_dp], [-g, g], joints(j)%lobatto)
            do ig = 1, 2
                fun = [-(1.0_dp - xis(ig)), -(1.0_dp + xis(ig)), 1.0_dp + xis(ig), &
                       1.0_dp - xis(ig)]/2.0_dp
                do k = 1, 4
                    bee(1, 2*k - 1:2*k) = fun(k)*n
                    bee(2, 2*k - 1:2*k) = fun(k)*t
                end do
                ds = length/2.0_dp
                if (joints(j)%axisymmetric) then
                    r = x1(1) + (1.0_dp + xis(ig))/2.0_dp*length*t(1)
                    ds = ds*r
                end if
                call check_matrix(error, geo%bee(1:2, :, ig), bee, 'joint B by hand')
                if (allocated(error)) return
                call check(error, all(geo%bee(3:4, :, ig) == 0.0_dp), 'joint rows 3:4 zero')
                if (allocated(error)) return
                call check(error, geo%dv(ig), ds, 'joint dS = L/2 (r L/2)', rel=tol)
                if (allocated(error)) return
            end do
        end do
    end subroutine test_joint

    !> make_elements keeps one record per element of each kind, each that element's geometry
    !> from its coordinates: a parallelogram quad (by hand) and a joint on its top face.
    subroutine test_library(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(element_box_t), allocatable :: library(:)
        type(element_geometry_t) :: geo
        real(dp) :: bee(4, 8), det, points(2, 4), weights(4)
        integer :: ig
        model%mesh%nnode = 6
        model%mesh%nelem = 2
        model%mesh%x = reshape([parallelogram(), x0 + a + c, b, x0 + c, b], [2, 6])
        model%mesh%conn = reshape([1, 2, 3, 4, 4, 3, 5, 6], [4, 2])
        model%mesh%kind = [elem_quad4, elem_joint_gauss]
        call make_elements(model, library, error)
        if (allocated(error)) return
        call check(error, library(elem_quad4)%slot(1) == 1 .and. &
                   library(elem_joint_gauss)%slot(2) == 1 .and. &
                   size(library(elem_quad4)%geometry) == 1 .and. &
                   size(library(elem_joint_gauss)%geometry) == 1, 'one record per element')
        if (allocated(error)) return
        call gauss_2x2(points, weights)
        do ig = 1, 4
            call b_by_hand(points(1, ig), points(2, ig), bee, det)
            call check_matrix(error, library(elem_quad4)%geometry(1)%bee(:, :, ig), bee, &
                              'library B by hand (parallelogram)')
            if (allocated(error)) return
        end do
        call library(elem_joint_gauss)%element%geometry(model%mesh%x(:, [4, 3, 5, 6]), geo)
        call check(error, all(library(elem_joint_gauss)%geometry(1)%bee == geo%bee) .and. &
                   all(library(elem_joint_gauss)%geometry(1)%dv == geo%dv), &
                   'library joint record = joint geometry of its nodes')
    end subroutine test_library

    !> The stiffness of a standard quad, taken over B's nonzero entries, against the full
    !> product sum_g B_g^T (D_g B_g dV_g) of the same stored B (matmul), plane strain and
    !> axisymmetric, with a full (unsymmetric) D different at each point.
    subroutine test_kernel(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quads(2)
        type(element_geometry_t) :: geo
        real(dp) :: dmat(4, 4, 4), ke(8, 8), full(8, 8), x(2, 4)
        integer :: q, ig, i, j
        quads = [quad4_t(), quad4_t(axisymmetric=.true.)]
        do ig = 1, 4
            do j = 1, 4
                do i = 1, 4
                    dmat(i, j, ig) = 1.0e4_dp*(1.0_dp + merge(3.0_dp, 0.0_dp, i == j)) + &
                                     37.0_dp*i - 11.0_dp*j + 5.0_dp*ig
                end do
            end do
        end do
        x = x_distorted
        x(1, :) = x(1, :) + 1.0_dp
        do q = 1, size(quads)
            call quads(q)%geometry(x, geo)
            call quads(q)%stiffness(geo, dmat, ke)
            full = 0.0_dp
            do ig = 1, 4
                full = full + matmul(transpose(geo%bee(:, :, ig)), &
                                     matmul(dmat(:, :, ig), geo%bee(:, :, ig))*geo%dv(ig))
            end do
            call check_matrix(error, ke, full, 'K over the nonzeros = full product')
            if (allocated(error)) return
        end do
    end subroutine test_kernel

    !> The strains of a standard quad, taken over B's nonzero entries, against the full
    !> product B_g u of the same stored B (matmul), plane strain and axisymmetric.
    subroutine test_strains_kernel(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quads(2)
        type(element_geometry_t) :: geo
        real(dp) :: u(8), strain(4, 4), full(4, 4), x(2, 4)
        integer :: q, ig, j
        quads = [quad4_t(), quad4_t(axisymmetric=.true.)]
        u = [(0.01_dp*j - 0.003_dp*j*j, j=1, 8)]
        x = x_distorted
        x(1, :) = x(1, :) + 1.0_dp
        do q = 1, size(quads)
            call quads(q)%geometry(x, geo)
            call quads(q)%strains(geo, u, strain)
            do ig = 1, 4
                full(:, ig) = matmul(geo%bee(:, :, ig), u)
            end do
            call check_matrix(error, strain, full, 'strains over the nonzeros = B u')
            if (allocated(error)) return
        end do
    end subroutine test_strains_kernel
end module test_elements_geometry
