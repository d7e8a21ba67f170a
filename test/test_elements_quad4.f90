!> Tests of the 4-node quad, its shape functions, loads and the elastic law, each against a
!> closed form.
module test_elements_quad4
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_shape, only: shape_fun, shape_der, quad4_corner_xi, quad4_corner_eta
    use cfrd_quad4, only: quad4_t
    use cfrd_elastic, only: elastic_dmatrix, constrained_modulus
    use cfrd_edge_load, only: face_pressure_forces
    use cfrd_principal, only: principal_stresses
    use cfrd_model, only: model_t, stage_t, stage_load, elem_quad4_shear
    use cfrd_results, only: results_t
    use cfrd_stage_driver, only: run_analysis
    use cfrd_test_models, only: new_model, elastic_material, add_pressure
    implicit none
    private

    public :: collect_elements_quad4

    !> A distorted quad (counter-clockwise), used where the closed form holds for any shape.
    real(dp), parameter :: x_distorted(2, 4) = reshape([0.0_dp, 0.0_dp, 2.0_dp, 0.3_dp, &
                                                        2.4_dp, 1.7_dp, -0.2_dp, 1.1_dp], [2, 4])
    real(dp), parameter :: e_mod = 3.0e4_dp, nu = 0.3_dp

contains

    subroutine collect_elements_quad4(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('shape_functions_kronecker', test_kronecker), &
                new_unittest('shape_derivatives_sum_zero', test_derivative_sum), &
                new_unittest('rigid_body_modes_free', test_rigid_modes), &
                new_unittest('constant_stress_edge_forces', test_constant_stress), &
                new_unittest('stiffness_symmetric', test_symmetry), &
                new_unittest('body_force_total', test_body_force), &
                new_unittest('pressure_resultant_and_moment', test_pressure), &
                new_unittest('plane_strain_sigma_zz', test_sigma_zz), &
                new_unittest('principal_stresses', test_principal), &
                new_unittest('q4s_rigid_modes_and_constant_strain', test_q4s_patch), &
                new_unittest('q4s_cantilever_pure_bending', test_q4s_bending) &
                ]
    end subroutine collect_elements_quad4

    !> N_i at node j is the Kronecker delta (definition of nodal shape functions).
    subroutine test_kronecker(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: fun(4)
        integer :: i, j
        do j = 1, 4
            fun = shape_fun(quad4_corner_xi(j), quad4_corner_eta(j))
            do i = 1, 4
                call check(error, fun(i), merge(1.0_dp, 0.0_dp, i == j), 'N_i(node j)', abs=1e-15_dp)
                if (allocated(error)) return
            end do
        end do
    end subroutine test_kronecker

    !> Partition of unity: the derivatives sum to zero at any point.
    subroutine test_derivative_sum(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: der(2, 4)
        der = shape_der(0.3_dp, -0.7_dp)
        call check(error, sum(der(1, :)), 0.0_dp, 'sum dN/dxi', abs=1e-15_dp)
        if (allocated(error)) return
        call check(error, sum(der(2, :)), 0.0_dp, 'sum dN/deta', abs=1e-15_dp)
    end subroutine test_derivative_sum

    !> Rigid translations and the infinitesimal rotation cause no force: K r = 0.
    subroutine test_rigid_modes(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quad
        real(dp) :: ke(8, 8), dmat(4, 4, 4), r(8, 3), f(8)
        integer :: k, mode
        call all_points(elastic_dmatrix(e_mod, nu), dmat)
        call quad%stiffness(x_distorted, dmat, ke)
        do k = 1, 4
            r(2*k - 1:2*k, 1) = [1.0_dp, 0.0_dp]
            r(2*k - 1:2*k, 2) = [0.0_dp, 1.0_dp]
            r(2*k - 1:2*k, 3) = [-x_distorted(2, k), x_distorted(1, k)]
        end do
        do mode = 1, 3
            f = matmul(ke, r(:, mode))
            call check(error, maxval(abs(f)), 0.0_dp, 'rigid mode force', &
                       abs=1e-10_dp*maxval(abs(ke)))
            if (allocated(error)) return
        end do
    end subroutine test_rigid_modes

    !> A w x h rectangle strained uniformly in x (eps_yy = 0 held): the nodal forces are those
    !> of the uniform edge tractions sigma_xx = M eps on the vertical edges (sigma_xx h / 2 per
    !> node) and sigma_yy = nu/(1-nu) M eps on the horizontal ones (sigma_yy w / 2 per node).
    subroutine test_constant_stress(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quad
        real(dp), parameter :: w = 3.0_dp, h = 2.0_dp, eps = 1.0e-3_dp
        real(dp) :: x(2, 4), ke(8, 8), dmat(4, 4, 4), u(8), f(8), strain(4, 4), sigma_xx, &
                    sigma_yy
        integer :: k
        x = reshape([0.0_dp, 0.0_dp, w, 0.0_dp, w, h, 0.0_dp, h], [2, 4])
        call all_points(elastic_dmatrix(e_mod, nu), dmat)
        call quad%stiffness(x, dmat, ke)
        do k = 1, 4
            u(2*k - 1:2*k) = [eps*x(1, k), 0.0_dp]
        end do
        f = matmul(ke, u)
        sigma_xx = constrained_modulus(e_mod, nu)*eps
        call check(error, f(3), sigma_xx*h/2.0_dp, 'force x at node 2', rel=1e-12_dp)
        if (allocated(error)) return
        call check(error, f(1), -sigma_xx*h/2.0_dp, 'force x at node 1', rel=1e-12_dp)
        if (allocated(error)) return
        sigma_yy = nu/(1.0_dp - nu)*sigma_xx
        call check(error, f(2), -sigma_yy*w/2.0_dp, 'force y at node 1', rel=1e-12_dp)
        if (allocated(error)) return
        call check(error, f(6), sigma_yy*w/2.0_dp, 'force y at node 3', rel=1e-12_dp)
        if (allocated(error)) return
        call quad%strains(x, u, strain)
        call check(error, strain(1, 3), eps, 'strain xx at a Gauss point', rel=1e-12_dp)
    end subroutine test_constant_stress

    subroutine test_symmetry(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quad
        real(dp) :: ke(8, 8), dmat(4, 4, 4)
        call all_points(elastic_dmatrix(e_mod, nu), dmat)
        call quad%stiffness(x_distorted, dmat, ke)
        call check(error, maxval(abs(ke - transpose(ke))), 0.0_dp, 'K - K^T', &
                   abs=1e-12_dp*maxval(abs(ke)))
    end subroutine test_symmetry

    !> The equivalent nodal forces of a uniform body force sum to b times the area
    !> (shoelace formula); 2x2 Gauss integrates det J (bilinear) exactly.
    subroutine test_body_force(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quad
        real(dp) :: fe(8), area
        integer :: k, j
        area = 0.0_dp
        do k = 1, 4
            j = mod(k, 4) + 1
            area = area + 0.5_dp*(x_distorted(1, k)*x_distorted(2, j) &
                                  - x_distorted(1, j)*x_distorted(2, k))
        end do
        call quad%body_force(x_distorted, [0.0_dp, -21.0_dp], fe)
        call check(error, sum(fe(2:8:2)), -21.0_dp*area, 'total body force y', rel=1e-13_dp)
        if (allocated(error)) return
        call check(error, sum(fe(1:7:2)), 0.0_dp, 'total body force x', abs=1e-13_dp)
    end subroutine test_body_force

    !> A linear pressure 10 -> 40 kPa on a face of length 5 along +x (element above it):
    !> resultant (10+40)/2 * 5 = 125 kN/m pushing up (+y), acting at the centroid of the
    !> trapezoidal load, x = L (p1 + 2 p2) / (3 (p1 + p2)) = 3.0 m from xa.
    subroutine test_pressure(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: fa(2), fb(2)
        call face_pressure_forces([0.0_dp, 0.0_dp], [5.0_dp, 0.0_dp], 10.0_dp, 40.0_dp, fa, fb)
        call check(error, fa(2) + fb(2), 125.0_dp, 'resultant', rel=1e-14_dp)
        if (allocated(error)) return
        call check(error, fb(2)*5.0_dp/(fa(2) + fb(2)), 3.0_dp, 'line of action', rel=1e-14_dp)
        if (allocated(error)) return
        call check(error, abs(fa(1)) + abs(fb(1)), 0.0_dp, 'no tangential force', abs=1e-14_dp)
    end subroutine test_pressure

    !> Plane strain: sigma_zz = nu (sigma_xx + sigma_yy) for eps_zz = 0.
    subroutine test_sigma_zz(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: s(4)
        s = matmul(elastic_dmatrix(e_mod, nu), [1.0e-3_dp, -4.0e-4_dp, 0.0_dp, 2.0e-4_dp])
        call check(error, s(3), nu*(s(1) + s(2)), 'sigma_zz', rel=1e-14_dp)
        if (allocated(error)) return
        call check(error, s(4), e_mod/(2.0_dp*(1.0_dp + nu))*2.0e-4_dp, 'tau = G gamma', &
                   rel=1e-14_dp)
    end subroutine test_sigma_zz

    !> Mohr's circle of (3, 1, tau 1): centre 2, radius sqrt 2, angle 22.5 degrees.
    subroutine test_principal(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: p(3)
        p = principal_stresses([3.0_dp, 1.0_dp, 0.0_dp, 1.0_dp])
        call check(error, p(1), 2.0_dp + sqrt(2.0_dp), 'sigma1', rel=1e-15_dp)
        if (allocated(error)) return
        call check(error, p(2), 2.0_dp - sqrt(2.0_dp), 'sigma3', rel=1e-15_dp)
        if (allocated(error)) return
        call check(error, p(3), 22.5_dp, 'angle', rel=1e-14_dp)
    end subroutine test_principal

    pure subroutine all_points(d, dmat)
        real(dp), intent(in) :: d(4, 4)
        real(dp), intent(out) :: dmat(4, 4, 4)
        integer :: ig
        do ig = 1, 4
            dmat(:, :, ig) = d
        end do
    end subroutine all_points

    !> Q4S (the natural shear strain of the centre) keeps what the quad must: on the distorted
    !> quad, the three rigid-body modes give no force (1e-10 of K), and a uniform strain
    !> field (linear displacements) gives the same strains at every Gauss point (1e-12),
    !> since its shear strain is the same at the centre: the patch test.
    subroutine test_q4s_patch(error)
        type(error_t), allocatable, intent(out) :: error
        type(quad4_t) :: quad
        real(dp) :: ke(8, 8), dmat(4, 4, 4), r(8, 3), f(8), u(8), strain(4, 4)
        real(dp), parameter :: grad(2, 2) = reshape([1.0e-3_dp, -4.0e-4_dp, 7.0e-4_dp, &
                                                     2.0e-4_dp], [2, 2])
        integer :: k, mode, ig
        quad = quad4_t(assumed_shear=.true.)
        call all_points(elastic_dmatrix(e_mod, nu), dmat)
        call quad%stiffness(x_distorted, dmat, ke)
        do k = 1, 4
            r(2*k - 1:2*k, 1) = [1.0_dp, 0.0_dp]
            r(2*k - 1:2*k, 2) = [0.0_dp, 1.0_dp]
            r(2*k - 1:2*k, 3) = [-x_distorted(2, k), x_distorted(1, k)]
            u(2*k - 1:2*k) = matmul(grad, x_distorted(:, k))
        end do
        do mode = 1, 3
            f = matmul(ke, r(:, mode))
            call check(error, maxval(abs(f)), 0.0_dp, 'Q4S rigid mode force', &
                       abs=1e-10_dp*maxval(abs(ke)))
            if (allocated(error)) return
        end do
        call quad%strains(x_distorted, u, strain)
        do ig = 1, 4
            call check(error, strain(1, ig), grad(1, 1), 'Q4S eps_xx', rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, strain(2, ig), grad(2, 2), 'Q4S eps_yy', rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, strain(4, ig), grad(1, 2) + grad(2, 1), 'Q4S gamma_xy', &
                       rel=1e-12_dp)
            if (allocated(error)) return
        end do
    end subroutine test_q4s_patch

    !> A cantilever 10 m long and 0.5 m deep (nu = 0) in pure bending: a moment M = 100
    !> kN m/m applied as the linear traction sigma_xx = M y / I on its end, x fixed at the
    !> root and y at its root's mid node. Beam theory, exact here: tip deflection
    !> v = M L^2 / (2 E I). 10 x 2 elements (each 1 x 0.25 m); rectangles, then every row
    !> sheared into parallelograms (the slab's shape: horizontal ends, 35 deg slope).
    !> Q4S: 1e-10 on rectangles, 6 % on parallelograms (the skew costs a little: their
    !> normal strains stay bilinear); Q4 locks (a third of the deflection, reported).
    subroutine test_q4s_bending(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: length = 10.0_dp, depth = 0.5_dp, e = 1.0e7_dp, moment = 100.0_dp
        real(dp) :: exact, tip(2, 2)
        integer :: kind, shape
        ! (downwards: the top fibre is in tension)
        exact = -moment*length**2/(2.0_dp*e*depth**3/12.0_dp)
        do shape = 1, 2
            do kind = 1, 2
                call cantilever(kind == 2, shape == 2, tip(kind, shape), error)
                if (allocated(error)) return
            end do
        end do
        write (*, '(a,4f9.4)') '  cantilever tip / beam theory: Q4, Q4S rectangles; Q4, Q4S '// &
            'parallelograms:', tip(:, 1)/exact, tip(:, 2)/exact
        call check(error, tip(2, 1), exact, 'Q4S rectangles, tip deflection', rel=1e-10_dp)
        if (allocated(error)) return
        call check(error, tip(2, 2), exact, 'Q4S parallelograms, tip deflection', rel=0.06_dp)
    contains
        subroutine cantilever(q4s, skewed, v, error)
            logical, intent(in) :: q4s, skewed
            real(dp), intent(out) :: v
            type(error_t), allocatable, intent(out) :: error
            integer, parameter :: nx = 10, ny = 2
            real(dp) :: x(2, (nx + 1)*(ny + 1)), yc, inertia
            integer :: conn(4, nx*ny), i, j, k
            type(model_t) :: model
            type(results_t) :: results
            do j = 0, ny
                do i = 0, nx
                    ! skewed: each row shifted along the beam by y / tan 35 deg
                    x(:, j*(nx + 1) + i + 1) = [length*i/nx + merge(depth*j/ny/0.7_dp, &
                                                0.0_dp, skewed), depth*j/ny - 0.5_dp*depth]
                end do
            end do
            k = 0
            do j = 0, ny - 1
                do i = 1, nx
                    k = k + 1
                    conn(:, k) = [j*(nx + 1) + i, j*(nx + 1) + i + 1, &
                                  (j + 1)*(nx + 1) + i + 1, (j + 1)*(nx + 1) + i]
                end do
            end do
            call new_model(model, x, conn, [(1, i=1, nx*ny)], [elastic_material(e, 0.0_dp, &
                                                                                0.0_dp)])
            allocate (model%slab_groups(0), model%gauges(0), model%wet_faces(0))
            if (q4s) model%mesh%kind = elem_quad4_shear
            do j = 0, ny
                model%fixed(1, j*(nx + 1) + 1) = .true.
            end do
            model%fixed(2, (ny/2)*(nx + 1) + 1) = .true.
            inertia = depth**3/12.0_dp
            do j = 1, ny
                ! face 2 of the last element of row j: from y_(j-1) to y_j; p = -sigma_xx
                yc = depth*(j - 1)/ny - 0.5_dp*depth
                call add_pressure(model, j*nx, 2, -moment*yc/inertia, &
                                  -moment*(yc + depth/ny)/inertia)
            end do
            model%stages(1) = stage_t(kind=stage_load, load_set=1, increments=1, label='M')
            call run_analysis(model, results, error)
            if (allocated(error)) return
            v = results%stages(1)%displacement(2, (ny/2)*(nx + 1) + nx + 1)
        end subroutine cantilever
    end subroutine test_q4s_bending
end module test_elements_quad4
