!> Verification of the linear static analysis against closed forms (issue 3, section 5):
!> patch tests, the confined column under self-weight, and the rate of convergence on Lame's
!> thick-walled cylinder. Every case also checks that the reactions balance the load.
module test_analysis_verification
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_model, only: model_t, gravity_load_t, stage_t, stage_fill, newtop_count, &
                          newtop_zero, axisymmetric
    use cfrd_results, only: results_t
    use cfrd_elastic, only: elastic_dmatrix, constrained_modulus
    use cfrd_linear_static, only: solve_linear_static
    use cfrd_test_models, only: new_model, elastic_material, add_pressure, relative_imbalance
    implicit none
    private

    public :: collect_analysis_verification

    real(dp), parameter :: pi = 3.14159265358979323846_dp

contains

    subroutine collect_analysis_verification(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('patch_test_displacement', test_patch_displacement), &
                new_unittest('patch_test_traction', test_patch_traction), &
                new_unittest('confined_column_uniform', test_column_uniform), &
                new_unittest('confined_column_graded', test_column_graded), &
                new_unittest('lame_cylinder_rate', test_lame_rate), &
                new_unittest('layered_column_newtop_zero', test_layers_zero), &
                new_unittest('layered_column_newtop_count', test_layers_count), &
                new_unittest('layered_column_limit_rate', test_layers_limit), &
                new_unittest('axisymmetric_triaxial_patch', test_axisymmetric_patch) &
                ]
    end subroutine collect_analysis_verification

    !> The distorted five-element patch of MacNeal & Harder (1985): 0.24 x 0.12 with interior
    !> nodes (0.04,0.02), (0.18,0.03), (0.16,0.08), (0.08,0.08).
    subroutine patch_model(model)
        type(model_t), intent(out) :: model
        real(dp), parameter :: x(2, 8) = reshape([0.0_dp, 0.0_dp, 0.24_dp, 0.0_dp, &
                                                  0.24_dp, 0.12_dp, 0.0_dp, 0.12_dp, &
                                                  0.04_dp, 0.02_dp, 0.18_dp, 0.03_dp, &
                                                  0.16_dp, 0.08_dp, 0.08_dp, 0.08_dp], [2, 8])
        integer, parameter :: conn(4, 5) = reshape([1, 2, 6, 5, 2, 3, 7, 6, 3, 4, 8, 7, &
                                                    4, 1, 5, 8, 5, 6, 7, 8], [4, 5])
        call new_model(model, x, conn, [1, 1, 1, 1, 1], [elastic_material(1.0e6_dp, 0.25_dp, &
                                                                          0.0_dp)])
    end subroutine patch_model

    !> Boundary nodes moved by the linear field ux = 1e-3 (x + y/2), uy = 1e-3 (y + x/2):
    !> the exact solution is that field everywhere, with uniform strain (1e-3, 1e-3, 0, 1e-3).
    !> Reference: the field itself and D eps (closed form); tolerance 1e-10 relative (rounding).
    subroutine test_patch_displacement(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        real(dp) :: exact(2), sigma(4)
        integer :: node, e, ig
        call patch_model(model)
        do node = 1, 4
            model%fixed(:, node) = .true.
            model%prescribed(:, node) = linear_field(model%mesh%x(:, node))
        end do
        call solve_linear_static(model, results, error)
        if (allocated(error)) return
        associate (stage => results%stages(1))
            do node = 5, 8
                exact = linear_field(model%mesh%x(:, node))
                call check(error, norm2(stage%displacement(:, node) - exact), 0.0_dp, &
                           'interior node displacement', abs=1e-10_dp*norm2(exact))
                if (allocated(error)) return
            end do
            sigma = matmul(elastic_dmatrix(1.0e6_dp, 0.25_dp), &
                           [1.0e-3_dp, 1.0e-3_dp, 0.0_dp, 1.0e-3_dp])
            do e = 1, 5
                do ig = 1, 4
                    call check(error, maxval(abs(stage%stress_gauss(:, ig, e) - sigma)), &
                               0.0_dp, 'Gauss point stress', abs=1e-10_dp*maxval(abs(sigma)))
                    if (allocated(error)) return
                end do
            end do
            call check(error, norm2(stage%reaction_sum), 0.0_dp, &
                       'reactions of a self-equilibrated patch', &
                       abs=1e-9_dp*maxval(abs(stage%reaction)))
        end associate
    contains
        pure function linear_field(p) result(u)
            real(dp), intent(in) :: p(2)
            real(dp) :: u(2)
            u = 1.0e-3_dp*[p(1) + p(2)/2.0_dp, p(2) + p(1)/2.0_dp]
        end function linear_field
    end subroutine test_patch_displacement

    !> The same patch loaded by a uniform tension of 1000 kPa on its right edge (a negative
    !> pressure on face 1 of element 2), held only against rigid motion: the exact stress is
    !> sigma_xx = 1000, sigma_yy = sigma_xy = 0, sigma_zz = nu sigma_xx (plane strain).
    subroutine test_patch_traction(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        real(dp), parameter :: s = 1000.0_dp
        real(dp) :: sigma(4)
        integer :: e, ig
        call patch_model(model)
        model%fixed(:, 1) = .true.          ! pin at the origin
        model%fixed(1, 4) = .true.          ! roller above it: no rotation
        call add_pressure(model, 2, 1, -s, -s)
        call solve_linear_static(model, results, error)
        if (allocated(error)) return
        sigma = [s, 0.0_dp, 0.25_dp*s, 0.0_dp]
        associate (stage => results%stages(1))
            do e = 1, 5
                do ig = 1, 4
                    call check(error, maxval(abs(stage%stress_gauss(:, ig, e) - sigma)), &
                               0.0_dp, 'Gauss point stress', abs=1e-10_dp*s)
                    if (allocated(error)) return
                end do
            end do
            call check(error, stage%applied_load(1), s*0.12_dp, 'applied force', rel=1e-13_dp)
            if (allocated(error)) return
            call check(error, relative_imbalance(stage%applied_load, stage%reaction_sum), &
                       0.0_dp, 'reaction balance', abs=1e-9_dp)
        end associate
    end subroutine test_patch_traction

    !> A column one element wide, sides held in x, base fixed, under its own weight: a 1D bar.
    !> Closed form u(z) = -gamma (H z - z^2/2) / M. Linear elements with consistent loads are
    !> nodally exact in 1D (the Green's function lies in the element space), so nodal values
    !> must match to rounding: 1e-10 relative to the top settlement.
    subroutine column_case(error, heights)
        type(error_t), allocatable, intent(out) :: error
        real(dp), intent(in) :: heights(:)
        real(dp), parameter :: gamma = 20.0_dp, e_mod = 2.0e4_dp, nu = 0.3_dp
        type(model_t) :: model
        type(results_t) :: results
        real(dp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
        real(dp) :: z, h, m, exact, scale
        integer :: n, i, node
        n = size(heights)
        allocate (x(2, 2*(n + 1)), conn(4, n))
        z = 0.0_dp
        do i = 0, n
            if (i > 0) z = z + heights(i)
            x(:, 2*i + 1) = [0.0_dp, z]
            x(:, 2*i + 2) = [1.0_dp, z]
        end do
        h = z
        do i = 1, n
            conn(:, i) = [2*i - 1, 2*i, 2*i + 2, 2*i + 1]
        end do
        call new_model(model, x, conn, [(1, i=1, n)], [elastic_material(e_mod, nu, gamma)])
        model%fixed(1, :) = .true.
        model%fixed(2, 1:2) = .true.
        model%load_sets(1)%gravity = [gravity_load_t()]
        call solve_linear_static(model, results, error)
        if (allocated(error)) return
        m = constrained_modulus(e_mod, nu)
        scale = gamma*h**2/(2.0_dp*m)
        do node = 1, size(x, 2)
            z = x(2, node)
            exact = -gamma*(h*z - z**2/2.0_dp)/m
            call check(error, results%stages(1)%displacement(2, node), exact, &
                       'settlement at a node', abs=1e-10_dp*scale)
            if (allocated(error)) return
        end do
        associate (stage => results%stages(1))
            call check(error, stage%applied_load(2), -gamma*h, 'weight of the column', &
                       rel=1e-13_dp)
            if (allocated(error)) return
            call check(error, relative_imbalance(stage%applied_load, stage%reaction_sum), &
                       0.0_dp, 'reaction balance', abs=1e-9_dp)
        end associate
    end subroutine column_case

    subroutine test_column_uniform(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: heights(10)
        heights = 1.0_dp
        call column_case(error, heights)
    end subroutine test_column_uniform

    !> Nodal exactness does not depend on equal spacing: graded element heights.
    subroutine test_column_graded(error)
        type(error_t), allocatable, intent(out) :: error
        call column_case(error, [0.5_dp, 0.7_dp, 1.3_dp, 2.0_dp, 3.1_dp, 0.4_dp, 2.2_dp])
    end subroutine test_column_graded

    !> Lame's thick-walled cylinder (plane strain, inner radius a, outer b, inner pressure p):
    !> u_r(r) = (1+nu) p a^2 / (E (b^2 - a^2)) ((1 - 2 nu) r + b^2 / r). A quarter with
    !> symmetry conditions, meshed n x n in (r, theta). The largest nodal error of u_r must fall
    !> at rate 2 under halving (bilinear elements, straight-sided boundary: both O(h^2)).
    subroutine test_lame_rate(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: err(3), rate
        integer :: k
        do k = 1, 3
            call lame_error(4*2**k, err(k), error)
            if (allocated(error)) return
        end do
        do k = 1, 2
            rate = log(err(k)/err(k + 1))/log(2.0_dp)
            write (*, '(a,i0,a,es10.3,a,f6.3)') '  lame: n = ', 4*2**k, ' error ', err(k), &
                ' rate ', rate
            call check(error, rate, 2.0_dp, 'convergence rate of u_r under halving', abs=0.2_dp)
            if (allocated(error)) return
        end do
    end subroutine test_lame_rate

    subroutine lame_error(n, err, error)
        integer, intent(in) :: n
        real(dp), intent(out) :: err
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: a = 1.0_dp, b = 2.0_dp, p = 100.0_dp, e_mod = 1.0e4_dp, &
                               nu = 0.3_dp
        type(model_t) :: model
        type(results_t) :: results
        real(dp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
        real(dp) :: r, theta, ur, exact, c
        integer :: i, j, node, e
        allocate (x(2, (n + 1)**2), conn(4, n*n))
        do j = 0, n
            do i = 0, n
                r = a + (b - a)*i/n
                theta = 0.5_dp*pi*j/n
                x(:, j*(n + 1) + i + 1) = [r*cos(theta), r*sin(theta)]
            end do
        end do
        do j = 0, n - 1
            do i = 0, n - 1
                node = j*(n + 1) + i + 1
                conn(:, j*n + i + 1) = [node, node + 1, node + n + 2, node + n + 1]
            end do
        end do
        call new_model(model, x, conn, [(1, i=1, n*n)], [elastic_material(e_mod, nu, 0.0_dp)])
        do i = 0, n
            model%fixed(2, i + 1) = .true.                 ! theta = 0: u_y = 0
            model%fixed(1, n*(n + 1) + i + 1) = .true.     ! theta = 90: u_x = 0
        end do
        do j = 0, n - 1
            e = j*n + 1
            call add_pressure(model, e, 4, p, p)           ! face 4 lies on r = a
        end do
        call solve_linear_static(model, results, error)
        if (allocated(error)) return
        c = (1.0_dp + nu)*p*a**2/(e_mod*(b**2 - a**2))
        err = 0.0_dp
        do node = 1, size(x, 2)
            r = norm2(x(:, node))
            ur = dot_product(results%stages(1)%displacement(:, node), x(:, node))/r
            exact = c*((1.0_dp - 2.0_dp*nu)*r + b**2/r)
            err = max(err, abs(ur - exact))
        end do
        err = err/(c*((1.0_dp - 2.0_dp*nu)*a + b**2/a))
        associate (stage => results%stages(1))
            ! The supports carry the pressure's resultant on the quarter: p a in x and in y.
            call check(error, relative_imbalance(stage%applied_load, stage%reaction_sum), &
                       0.0_dp, 'reaction balance', abs=1e-9_dp)
        end associate
    end subroutine lame_error

    !> A column of n layers, one element each, placed one by one (FILL stages), sides held in
    !> x, base fixed: a 1D bar built in layers. docs/theory.md section 9 derives the
    !> settlement of level j (z = j h) at the end of construction:
    !>   NEWTOP = 0 (zeroed after placement): s_j = gamma h^2 j (n - j) / M = gamma z (H-z)/M,
    !>   NEWTOP = 1 (counted):                s_j = gamma h^2 (j - 1/2 + j (n - j)) / M.
    subroutine layered_column(n, newtop, settlement, exact, error)
        integer, intent(in) :: n, newtop
        real(dp), allocatable, intent(out) :: settlement(:), exact(:)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: gamma = 20.0_dp, e_mod = 3.0e4_dp, nu = 0.25_dp, height = 40.0_dp
        type(model_t) :: model
        type(results_t) :: results
        real(dp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
        real(dp) :: h, m
        integer :: i, j
        h = height/n
        allocate (x(2, 2*(n + 1)), conn(4, n))
        do i = 0, n
            x(:, 2*i + 1) = [0.0_dp, i*h]
            x(:, 2*i + 2) = [1.0_dp, i*h]
        end do
        do i = 1, n
            conn(:, i) = [2*i - 1, 2*i, 2*i + 2, 2*i + 1]
        end do
        call new_model(model, x, conn, [(1, i=1, n)], [elastic_material(e_mod, nu, gamma)])
        model%fixed(1, :) = .true.
        model%fixed(2, 1:2) = .true.
        model%newtop = newtop
        model%mesh%group = [(i, i=1, n)]
        deallocate (model%mesh%group_name)
        allocate (model%mesh%group_name(n))
        do i = 1, n
            write (model%mesh%group_name(i), '(a,i0)') 'L', i
        end do
        deallocate (model%stages)
        allocate (model%stages(n))
        do i = 1, n
            model%stages(i) = stage_t(kind=stage_fill, group=i, increments=1, label='FILL')
        end do
        call solve_linear_static(model, results, error)
        if (allocated(error)) return
        m = constrained_modulus(e_mod, nu)
        allocate (settlement(0:n), exact(0:n))
        do j = 0, n
            settlement(j) = -results%stages(n)%displacement(2, 2*j + 1)
            if (j == 0) then
                exact(j) = 0.0_dp
            else if (newtop == newtop_zero) then
                exact(j) = gamma*h**2*j*(n - j)/m
            else
                exact(j) = gamma*h**2*(j - 0.5_dp + j*(n - j))/m
            end if
        end do
        associate (stage => results%stages(n))
            call check(error, relative_imbalance(stage%applied_load, stage%reaction_sum), &
                       0.0_dp, 'reaction balance of the built column', abs=1e-9_dp)
            if (allocated(error)) return
            call check(error, -stage%applied_load(2), gamma*height, 'weight placed', &
                       rel=1e-12_dp)
        end associate
    end subroutine layered_column

    subroutine test_layers_zero(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: s(:), exact(:)
        call layered_column(10, newtop_zero, s, exact, error)
        if (allocated(error)) return
        call check(error, maxval(abs(s - exact)), 0.0_dp, 'settlements, NEWTOP = 0', &
                   abs=1e-9_dp*maxval(exact))
    end subroutine test_layers_zero

    subroutine test_layers_count(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: s(:), exact(:)
        call layered_column(10, newtop_count, s, exact, error)
        if (allocated(error)) return
        call check(error, maxval(abs(s - exact)), 0.0_dp, 'settlements, NEWTOP = 1', &
                   abs=1e-9_dp*maxval(exact))
    end subroutine test_layers_count

    !> Counted settlements tend to gamma z (H - z) / M at rate O(1/n): the largest
    !> difference halves when n doubles (10, 20, 40 layers).
    subroutine test_layers_limit(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: s(:), exact(:)
        real(dp) :: diff(3)
        integer :: k, n
        do k = 1, 3
            n = 10*2**(k - 1)
            call layered_column(n, newtop_count, s, exact, error)
            if (allocated(error)) return
            diff(k) = maxval(abs(s(1:n) - limit_values(n)))/maxval(limit_values(n))
        end do
        do k = 1, 2
            call check(error, diff(k)/diff(k + 1), 2.0_dp, 'O(1/n) convergence to the limit', &
                       rel=0.05_dp)
            if (allocated(error)) return
        end do
    contains
        !> gamma z (H - z) / M at the levels of an n-layer column (same data as above).
        function limit_values(n) result(v)
            integer, intent(in) :: n
            real(dp), allocatable :: v(:)
            real(dp), parameter :: gamma = 20.0_dp, height = 40.0_dp
            real(dp) :: z, m
            integer :: i
            m = constrained_modulus(3.0e4_dp, 0.25_dp)
            allocate (v(n))
            do i = 1, n
                z = i*height/n
                v(i) = gamma*z*(height - z)/m
            end do
        end function limit_values
    end subroutine test_layers_limit

    !> An axisymmetric triaxial sample (radius 0.05 m, height 0.1 m, four distorted quads, one
    !> node on the axis) under a cell pressure p3 on its side and p1 on its top: the stress is
    !> uniform, sigma_r = sigma_theta = -p3, sigma_z = -p1, and u_r = eps_r r, u_z = eps_z z
    !> with eps_r = (sigma_r - nu (sigma_theta + sigma_z))/E (Hooke, closed form).
    subroutine test_axisymmetric_patch(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: r0 = 0.05_dp, h0 = 0.1_dp, e_mod = 1.0e4_dp, nu = 0.3_dp, &
                               p3 = 100.0_dp, p1 = 300.0_dp
        type(model_t) :: model
        type(results_t) :: results
        real(dp) :: x(2, 9), eps_r, eps_z, sigma(4)
        integer :: conn(4, 4), node, e, ig
        ! Nodes 1-3 at z = 0, 4-6 mid-height (node 5 moved off the grid), 7-9 on top.
        x = reshape([0.0_dp, 0.0_dp, 0.6_dp*r0, 0.0_dp, r0, 0.0_dp, &
                     0.0_dp, 0.45_dp*h0, 0.55_dp*r0, 0.55_dp*h0, r0, 0.5_dp*h0, &
                     0.0_dp, h0, 0.4_dp*r0, h0, r0, h0], [2, 9])
        conn = reshape([1, 2, 5, 4, 2, 3, 6, 5, 4, 5, 8, 7, 5, 6, 9, 8], [4, 4])
        call new_model(model, x, conn, [1, 1, 1, 1], [elastic_material(e_mod, nu, 0.0_dp)])
        model%analysis = axisymmetric
        model%fixed(1, [1, 4, 7]) = .true.      ! the axis: u_r = 0
        model%fixed(2, 1:3) = .true.            ! the base: u_z = 0
        call add_pressure(model, 2, 2, p3, p3)  ! side r = r0 of elements 2 and 4
        call add_pressure(model, 4, 2, p3, p3)
        call add_pressure(model, 3, 3, p1, p1)  ! top of elements 3 and 4
        call add_pressure(model, 4, 3, p1, p1)
        call solve_linear_static(model, results, error)
        if (allocated(error)) return
        eps_r = (-p3 - nu*(-p3 - p1))/e_mod
        eps_z = (-p1 - nu*(-2.0_dp*p3))/e_mod
        sigma = [-p3, -p1, -p3, 0.0_dp]
        associate (stage => results%stages(1))
            do node = 1, 9
                call check(error, stage%displacement(1, node), eps_r*x(1, node), 'u_r', &
                           abs=1e-10_dp*abs(eps_r)*r0)
                if (allocated(error)) return
                call check(error, stage%displacement(2, node), eps_z*x(2, node), 'u_z', &
                           abs=1e-10_dp*abs(eps_z)*h0)
                if (allocated(error)) return
            end do
            do e = 1, 4
                do ig = 1, 4
                    call check(error, maxval(abs(stage%stress_gauss(:, ig, e) - sigma)), &
                               0.0_dp, 'Gauss point stress', abs=1e-9_dp*p1)
                    if (allocated(error)) return
                end do
            end do
            ! Per radian: the top carries p1 r0^2 / 2, the side p3 r0 h0.
            call check(error, stage%applied_load(2), -p1*r0**2/2.0_dp, 'axial load', &
                       rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, stage%applied_load(1), -p3*r0*h0, 'radial load', rel=1e-12_dp)
            if (allocated(error)) return
            ! Only the axial forces balance: radially, the hoop stress of the wedge's sides
            ! carries the difference (integral of sigma_theta / r over the volume).
            call check(error, stage%applied_load(2) + stage%reaction_sum(2), 0.0_dp, &
                       'axial reaction balance', abs=1e-9_dp*abs(stage%applied_load(2)))
        end associate
    end subroutine test_axisymmetric_patch
end module test_analysis_verification
