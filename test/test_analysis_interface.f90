!> The slab-cushion interface, methods one and two (issue 6, section 4): the Goodman joint's
!> patch test, the Coulomb limit, the traction oscillation of stiff joints under Gauss and
!> Newton-Cotes integration, and the thin layer tending to a joint as it gets thinner.
!> Each model is two blocks, one on top of the other, joined along y = hb by joints or a
!> thin layer (built in code, independent of the deck reader).
module test_analysis_interface
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check, fail
    use cfrd_model, only: model_t, material_t, stage_t, stage_load, load_set_t, &
                          interface_element_t, pressure_load_t, gravity_load_t, &
                          elem_quad4, elem_joint_gauss, elem_joint_lobatto, &
                          method_joint, method_thin, solver_newton
    use cfrd_results, only: results_t
    use cfrd_stage_driver, only: run_analysis
    use cfrd_interface, only: interface_stations, phase_openings, open_gap, slab_stresses
    use cfrd_results, only: interface_result_t, opening_t, slab_result_t
    use cfrd_test_models, only: new_model, elastic_material, edge_traction, linear_joint
    use cfrd_goodman, only: goodman_params_t, goodman_update, goodman_update_tangent
    implicit none
    private

    public :: collect_analysis_interface

    real(dp), parameter :: deg = 0.017453292519943295769_dp

contains

    subroutine collect_analysis_interface(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('joint_patch_gauss', test_patch_gauss), &
                new_unittest('joint_patch_lobatto', test_patch_lobatto), &
                new_unittest('coulomb_limit', test_coulomb), &
                new_unittest('joint_consistent_tangent', test_joint_tangent), &
                new_unittest('joint_newton_quadratic', test_joint_newton), &
                new_unittest('stiff_joint_oscillation', test_oscillation), &
                new_unittest('stiff_joint_notch_oscillation', test_notch_oscillation), &
                new_unittest('thin_layer_tends_to_joint', test_thin_to_joint), &
                new_unittest('opening_width_and_depth', test_opening), &
                new_unittest('slab_section_resultants', test_slab_sections) &
                ]
    end subroutine collect_analysis_interface

    !> Two blocks of nx x ny quads, width w, heights hb (bottom) and ht (top), the top one
    !> `gap` above the bottom one, joined by nx interface elements of kind `kind` (material 2;
    !> the blocks are material 1), all rotated by `angle` degrees about the origin. Node
    !> numbers: bottom block row by row from y = 0, then the top block.
    subroutine two_blocks(model, nx, ny, w, hb, ht, gap, kind, block, joint, angle, first_joint)
        type(model_t), intent(out) :: model
        integer, intent(in) :: nx, ny, kind
        real(dp), intent(in) :: w, hb, ht, gap, angle
        type(material_t), intent(in) :: block, joint
        !> Interface elements only from column first_joint on (default 1); the columns
        !> before it are left unjoined, a crack between the blocks; nx + 1: no joints.
        integer, intent(in), optional :: first_joint
        real(dp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :), mat(:)
        real(dp) :: r(2, 2)
        integer :: i, j, e, nrow, first, njoint
        nrow = nx + 1
        first = 1
        if (present(first_joint)) first = first_joint
        njoint = nx - first + 1
        allocate (x(2, 2*nrow*(ny + 1)), conn(4, 2*nx*ny + njoint), mat(2*nx*ny + njoint))
        do j = 0, ny
            do i = 0, nx
                x(:, bottom(i, j)) = [w*i/nx, hb*j/ny]
                x(:, top(i, j)) = [w*i/nx, hb + gap + ht*j/ny]
            end do
        end do
        r = reshape([cos(angle*deg), sin(angle*deg), -sin(angle*deg), cos(angle*deg)], [2, 2])
        x = matmul(r, x)
        e = 0
        do j = 0, ny - 1
            do i = 0, nx - 1
                e = e + 1
                conn(:, e) = [bottom(i, j), bottom(i + 1, j), bottom(i + 1, j + 1), &
                              bottom(i, j + 1)]
                mat(e) = 1
                conn(:, e + nx*ny) = [top(i, j), top(i + 1, j), top(i + 1, j + 1), top(i, j + 1)]
                mat(e + nx*ny) = 1
            end do
        end do
        do i = first - 1, nx - 1
            e = 2*nx*ny + i - first + 2
            conn(:, e) = [bottom(i, ny), bottom(i + 1, ny), top(i + 1, 0), top(i, 0)]
            mat(e) = 2
        end do
        call new_model(model, x, conn, mat, [block, joint])
        model%mesh%kind(2*nx*ny + 1:) = kind
        allocate (model%interfaces(njoint))
        do i = 1, njoint
            model%interfaces(i) = interface_element_t(element=2*nx*ny + i, line=1, &
                method=merge(method_thin, method_joint, kind == elem_quad4))
        end do
        allocate (model%slab_groups(0), model%gauges(0), model%wet_faces(0))
    contains
        pure integer function bottom(i, j)
            integer, intent(in) :: i, j
            bottom = j*(nx + 1) + i + 1
        end function bottom
        pure integer function top(i, j)
            integer, intent(in) :: i, j
            top = (ny + 1)*(nx + 1) + j*(nx + 1) + i + 1
        end function top
    end subroutine two_blocks

    !> Patch test: blocks (nu = 0) under the uniform stress state sigma_nn = -p, tau = q in
    !> the frame rotated by 30 deg (top traction and the side tractions of that state, bottom
    !> fixed). The exact solution is linear in each block, so every joint station must carry
    !> (sigma_n, tau) = (-p, q) with relative displacements (-p/kn, q/ks): 1e-10 relative.
    subroutine patch_test(error, kind)
        type(error_t), allocatable, intent(out) :: error
        integer, intent(in) :: kind
        type(model_t) :: model
        type(results_t) :: results
        real(dp), parameter :: p = 200.0_dp, q = 60.0_dp, kn = 1.0e6_dp, ks = 2.0e4_dp, &
                               angle = 30.0_dp
        real(dp) :: t(2), n(2)
        integer, parameter :: nx = 4, ny = 2
        integer :: j, k, nb, i
        call two_blocks(model, nx, ny, 4.0_dp, 2.0_dp, 2.0_dp, 0.0_dp, kind, &
                        elastic_material(1.0e4_dp, 0.0_dp, 0.0_dp), linear_joint(kn, ks), angle)
        t = [cos(angle*deg), sin(angle*deg)]
        n = [-t(2), t(1)]
        nb = (nx + 1)*(ny + 1)
        model%fixed(:, 1:nx + 1) = .true.
        associate (f => model%load_sets(1)%nodal_force)
            ! Top face (normal n): traction sigma.n = -p n + q t.
            call edge_traction(model, [(nb + ny*(nx + 1) + i, i=1, nx + 1)], -p*n + q*t, f)
            ! Right sides (normal t): traction q n; left sides (normal -t): -q n.
            call edge_traction(model, [((j*(nx + 1) + nx + 1), j=0, ny)], q*n, f)
            call edge_traction(model, [(nb + (j*(nx + 1) + nx + 1), j=0, ny)], q*n, f)
            call edge_traction(model, [((j*(nx + 1) + 1), j=0, ny)], -q*n, f)
            call edge_traction(model, [(nb + (j*(nx + 1) + 1), j=0, ny)], -q*n, f)
        end associate
        model%stages(1) = stage_t(kind=stage_load, load_set=1, increments=1, label='PATCH')
        call run_analysis(model, results, error)
        if (allocated(error)) return
        associate (r => results%stages(1)%interface)
            do k = 1, nx
                do j = 1, 2
                    call check(error, r%sigma_n(j, k), -p, 'sigma_n', rel=1e-10_dp)
                    if (allocated(error)) return
                    call check(error, r%tau(j, k), q, 'tau', rel=1e-10_dp)
                    if (allocated(error)) return
                    call check(error, r%du_n(j, k), -p/kn, 'du_n', rel=1e-10_dp)
                    if (allocated(error)) return
                    call check(error, r%du_s(j, k), q/ks, 'du_s', rel=1e-10_dp)
                    if (allocated(error)) return
                end do
            end do
        end associate
    end subroutine patch_test

    subroutine test_patch_gauss(error)
        type(error_t), allocatable, intent(out) :: error
        call patch_test(error, elem_joint_gauss)
    end subroutine test_patch_gauss

    subroutine test_patch_lobatto(error)
        type(error_t), allocatable, intent(out) :: error
        call patch_test(error, elem_joint_lobatto)
    end subroutine test_patch_lobatto

    !> Coulomb limit (paper Table 4: phi 30 deg, k1 1000, n1 0.3): a block on a joint over a
    !> fixed base, pressed by p = 100 kPa (stage 1), then dragged sideways as a whole (every
    !> node's ux prescribed, stage 2, 40 increments), so that the joint sees constant
    !> sigma_n = -p and a uniform slip s. Eq. (7) at constant p integrates to the hyperbola
    !> tau = s / (1/ks_i + Rf1 s / tau_f), ks_i = k1 gamma_w (p/pa)^n1, tau_f = p tan phi
    !> (closed form). Rf1 = 1 (the paper's value): at s = 2 and 300 tau_f/ks_i tau is on the
    !> hyperbola (1e-10) and below tau_f at every stage; Rf1 = 0.9: at s = 30 tau_f/ks_i
    !> (past s = 10 tau_f/ks_i, where the hyperbola reaches tau_f) tau = tau_f (1e-12), the
    !> limit reached and no more.
    subroutine test_coulomb(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        type(material_t) :: joint
        integer, parameter :: nx = 4, ny = 1
        real(dp), parameter :: p = 100.0_dp
        real(dp) :: ks_i, tau_f, slip, expected
        real(dp), parameter :: slips(3) = [2.0_dp, 300.0_dp, 30.0_dp], rf(3) = [1.0_dp, 1.0_dp, &
                                                                              0.9_dp]
        integer :: k, s, nb, i, case
        joint = linear_joint(1.0e7_dp, 0.0_dp)
        joint%k1 = 1000.0_dp
        joint%n1 = 0.3_dp
        joint%rf1 = 1.0_dp
        joint%phi = 30.0_dp
        tau_f = p*tan(30.0_dp*deg)
        ks_i = 1000.0_dp*9.81_dp*(p/101.325_dp)**0.3_dp
        do case = 1, 3
            slip = slips(case)*tau_f/ks_i
            joint%rf1 = rf(case)
            call two_blocks(model, nx, ny, 4.0_dp, 1.0_dp, 1.0_dp, 0.0_dp, elem_joint_lobatto, &
                            elastic_material(1.0e5_dp, 0.2_dp, 0.0_dp), joint, 0.0_dp)
            model%pa = 101.325_dp
            nb = (nx + 1)*(ny + 1)
            model%fixed(:, 1:nb) = .true.
            model%fixed(1, nb + 1:) = .true.
            model%prescribed(1, nb + 1:) = slip
            deallocate (model%load_sets)
            allocate (model%load_sets(2))
            do s = 1, 2
                allocate (model%load_sets(s)%nodal_force(2, model%mesh%nnode), source=0.0_dp)
                allocate (model%load_sets(s)%gravity(0), model%load_sets(s)%pressures(0))
            end do
            model%load_sets(2)%name = 'NORMAL'
            model%load_sets(2)%pressures = [(pressure_load_t(element=2*nx*ny - nx + i, &
                                             face=3, p1=p, p2=p), i=1, nx)]
            model%stages = [stage_t(kind=stage_load, load_set=2, increments=1, label='PRESS'), &
                            stage_t(kind=stage_load, load_set=1, increments=40, label='DRAG')]
            call run_analysis(model, results, error)
            if (allocated(error)) return
            do s = 1, 2
                associate (r => results%stages(s)%interface)
                    if (any(abs(r%tau) > -r%sigma_n*tan(30.0_dp*deg)*(1.0_dp + 1.0e-12_dp))) then
                        call fail(error, 'a station above the Coulomb line')
                        return
                    end if
                end associate
            end do
            expected = min(slip/(1.0_dp/ks_i + rf(case)*slip/tau_f), tau_f)
            associate (r => results%stages(2)%interface)
                do k = 1, nx
                    call check(error, r%sigma_n(1, k), -p, 'sigma_n = -p', rel=1e-9_dp)
                    if (allocated(error)) return
                    call check(error, r%du_s(1, k), slip, 'slip', rel=1e-9_dp)
                    if (allocated(error)) return
                    call check(error, r%tau(1, k), expected, &
                               trim(merge('tau on the hyperbola', 'tau = tau_f         ', &
                                          case < 3)), rel=merge(1e-10_dp, 1e-12_dp, case < 3))
                    if (allocated(error)) return
                end do
            end associate
        end do
    end subroutine test_coulomb

    !> Newton's tangent of a joint (goodman_update_tangent) against central differences of
    !> the joint's update (goodman_update) with respect to the relative displacement
    !> increment, in every branch of the law (Table 4's parameters, Rf1 = 0.9): closed and
    !> loading; a slip against the shear stress, unloading only and past zero; the Coulomb cap
    !> reached within the increment (d tau / d du_n = -tan(phi) kn); Rf1 = 0 (no hyperbola);
    !> an open joint (kn_t; no shear, floored). Tolerance 1e-6 of the largest entry (the
    !> differences' truncation with a step 1e-4 of the increment is about 1e-8).
    subroutine test_joint_tangent(error)
        type(error_t), allocatable, intent(out) :: error
        type(goodman_params_t) :: p
        integer, parameter :: ncase = 7
        real(dp), parameter :: s0(2, ncase) = reshape([-200.0_dp, 50.0_dp, -200.0_dp, 50.0_dp, &
                                                       -200.0_dp, 50.0_dp, -200.0_dp, 90.0_dp, &
                                                       -200.0_dp, 30.0_dp, -300.0_dp, -40.0_dp, &
                                                       20.0_dp, 0.0_dp], [2, ncase])
        real(dp), parameter :: un0(ncase) = [-2.0e-5_dp, -2.0e-5_dp, -2.0e-5_dp, -2.0e-5_dp, &
                                             -2.0e-5_dp, -3.0e-5_dp, 2.0e-3_dp]
        real(dp), parameter :: de0(2, ncase) = reshape([-1.0e-5_dp, 2.0e-3_dp, &
                                                        -1.0e-5_dp, -1.0e-4_dp, &
                                                        -1.0e-5_dp, -8.0e-2_dp, &
                                                        1.5e-5_dp, 3.0e-1_dp, &
                                                        -1.0e-5_dp, 5.0e-3_dp, &
                                                        -2.0e-5_dp, -1.0e-3_dp, &
                                                        1.0e-4_dp, 1.0e-3_dp], [2, ncase])
        character(len=*), parameter :: names(ncase) = [character(len=24) :: 'closed, loading', &
            'reversal', 'reversal past zero', 'Coulomb cap', 'Rf1 = 0', 'negative shear', 'open']
        real(dp) :: c(2, 2), fd(2, 2), plus(2), minus(2), mid(2), de(2), h, scale
        integer :: k, j
        p = goodman_params_t(kn_compression=1.0e7_dp, kn_tension=1.0e4_dp, k1=1000.0_dp, &
                             n1=0.3_dp, rf1=0.9_dp, phi=30.0_dp)
        do k = 1, ncase
            p%rf1 = merge(0.0_dp, 0.9_dp, k == 5)
            call goodman_update_tangent(p, s0(:, k), un0(k), de0(:, k), c)
            do j = 1, 2
                h = 1.0e-4_dp*abs(de0(j, k))
                de = de0(:, k)
                de(j) = de(j) + h
                call goodman_update(p, s0(:, k), un0(k), de, .true., plus, mid)
                de(j) = de(j) - 2.0_dp*h
                call goodman_update(p, s0(:, k), un0(k), de, .true., minus, mid)
                fd(:, j) = (plus - minus)/(2.0_dp*h)
            end do
            if (k == 4) then
                call check(error, abs(fd(2, 1) + tan(30.0_dp*deg)*1.0e7_dp) < 1.0_dp, &
                           'the cap case is not at the cap')
                if (allocated(error)) return
            end if
            if (k == 7) then
                ! Open: no shear stress whatever the slip; the tangent floors it at 1e-4 ks_i.
                call check(error, all(abs(fd(2, :)) == 0.0_dp) .and. c(2, 2) > 0.0_dp .and. &
                           c(2, 2) <= 1.0e-4_dp*1000.0_dp*9.81_dp .and. c(2, 1) == 0.0_dp, &
                           'open joint: shear tangent not the floor')
                if (allocated(error)) return
                fd(2, 2) = c(2, 2)
            end if
            scale = maxval(abs(fd))
            call check(error, maxval(abs(c - fd)) <= 1.0e-6_dp*scale, &
                       'joint tangent, '//trim(names(k))//': analytic and central '// &
                       'differences differ')
            if (allocated(error)) return
        end do
    end subroutine test_joint_tangent

    !> Newton's rate on a joint that slips and compresses at once: a block pressed and dragged
    !> over a joint, in one increment to the Coulomb region of the hyperbola (Rf1 = 0.9,
    !> normal load and drag together, so that d tau / d du_n matters). Reference: the
    !> statics, the residual against the load; with the consistent tangent Newton reaches
    !> 1e-13 in one increment (7 iterations, residuals 2.2e-4, 1.6e-6, 7.8e-11, 3.6e-15 at the
    !> end: quadratic), where the material tangent of the end state contracted by 1/8 per
    !> iteration (28 cutbacks, 501 iterations).
    subroutine test_joint_newton(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        type(material_t) :: joint
        integer, parameter :: nx = 4, ny = 1
        integer :: nb, i
        joint = linear_joint(1.0e7_dp, 0.0_dp)
        joint%k1 = 1000.0_dp
        joint%n1 = 0.3_dp
        joint%rf1 = 0.9_dp
        joint%phi = 30.0_dp
        call two_blocks(model, nx, ny, 4.0_dp, 1.0_dp, 1.0_dp, 0.0_dp, elem_joint_lobatto, &
                        elastic_material(1.0e5_dp, 0.2_dp, 0.0_dp), joint, 0.0_dp)
        model%pa = 101.325_dp
        model%solver = solver_newton
        model%tolerance = 1.0e-13_dp
        model%max_iterations = 10
        nb = (nx + 1)*(ny + 1)
        model%fixed(:, 1:nb) = .true.
        deallocate (model%load_sets)
        allocate (model%load_sets(1))
        allocate (model%load_sets(1)%nodal_force(2, model%mesh%nnode), source=0.0_dp)
        allocate (model%load_sets(1)%gravity(0))
        ! 100 kPa normal and 0.5 tan(30 deg) of it in shear on the top face (4 m wide)
        model%load_sets(1)%pressures = [(pressure_load_t(element=2*nx*ny - nx + i, &
                                         face=3, p1=100.0_dp, p2=100.0_dp), i=1, nx)]
        model%load_sets(1)%nodal_force(1, model%mesh%nnode - nx:model%mesh%nnode) = &
            0.5_dp*100.0_dp*tan(30.0_dp*deg)*4.0_dp/real(nx, dp)* &
            [0.5_dp, (1.0_dp, i=1, nx - 1), 0.5_dp]
        model%stages = [stage_t(kind=stage_load, load_set=1, increments=1, label='PUSH')]
        call run_analysis(model, results, error)
        if (allocated(error)) return
        associate (r => results%stages(1))
            call check(error, r%max_residual <= 1.0e-13_dp .and. r%cutbacks == 0 .and. &
                       r%iterations <= 10, 'Newton did not reach 1e-13 in 10 iterations '// &
                       'with the consistent tangent')
        end associate
    end subroutine test_joint_newton

    !> Stations of the joint line in order along it, positions s and normal tractions y:
    !> both Gauss points of every element; Newton-Cotes stations, which sit on the nodes
    !> that neighbouring elements share, counted once.
    subroutine profile(results, lobatto, s, y)
        type(results_t), intent(in) :: results
        logical, intent(in) :: lobatto
        real(dp), allocatable, intent(out) :: s(:), y(:)
        integer :: n
        associate (r => results%stages(1)%interface)
            n = size(r%s, 2)
            if (lobatto) then
                s = [r%s(1, :), r%s(2, n)]
                y = [r%sigma_n(1, :), r%sigma_n(2, n)]
            else
                s = reshape(r%s, [2*n])
                y = reshape(r%sigma_n, [2*n])
            end if
        end associate
    end subroutine profile

    !> Zig-zag amplitude of a traction profile y at stations s (increasing), from the second
    !> divided differences D_i (the y'' of the parabola through stations i-1, i, i+1): a
    !> zig-zag of amplitude a on spacing h has |D| = 4 a / h^2, alternating in sign. Where
    !> two neighbouring D have opposite signs, the smaller of the two |D| h^2 / 4 (h the
    !> local mean spacing) is the zig-zag there; the largest over the line is returned. A
    !> smooth profile of any slope and any curvature of one sign gives 0, on any spacing
    !> (the Gauss stations alternate 0.58 h and 0.42 h apart); at an inflection it gives its
    !> third-derivative term, of order h^3 |y'''|.
    pure function zigzag(s, y) result(amp)
        real(dp), intent(in) :: s(:), y(:)
        real(dp) :: amp
        real(dp) :: d(size(y)), a(size(y))
        integer :: i
        d = 0.0_dp
        a = 0.0_dp
        do i = 2, size(y) - 1
            d(i) = 2.0_dp*((y(i + 1) - y(i))/(s(i + 1) - s(i)) - &
                           (y(i) - y(i - 1))/(s(i) - s(i - 1)))/(s(i + 1) - s(i - 1))
            a(i) = abs(d(i))*(0.5_dp*(s(i + 1) - s(i - 1)))**2/4.0_dp
        end do
        amp = 0.0_dp
        do i = 2, size(y) - 2
            if (d(i)*d(i + 1) < 0.0_dp) amp = max(amp, min(a(i), a(i + 1)))
        end do
    end function zigzag

    !> The issue's case: a stiff joint (kn = 1e3 and 1e6 times E / element size, 20
    !> elements) between a fixed block and a block on side rollers, under a normal traction
    !> rising linearly from 20 to 180 kPa along the top. Asserted: the Newton-Cotes traction
    !> zig-zags by less than 1 % of the mean (100 kPa). Found: so does Gauss' (below 1e-3 %
    !> at both ratios): a linear traction has no gradient steep enough to excite the
    !> oscillation (docs/theory.md section 12; the notched case below does).
    subroutine test_oscillation(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        integer, parameter :: nx = 20, ny = 4
        real(dp), parameter :: e_block = 1.0e4_dp, size = 1.0_dp, ratios(2) = [1.0e3_dp, 1.0e6_dp]
        real(dp), allocatable :: s(:), y(:)
        real(dp) :: amp(2, 2)
        integer :: r, rule, i, kinds(2)
        kinds = [elem_joint_gauss, elem_joint_lobatto]
        do r = 1, 2
            do rule = 1, 2
                call two_blocks(model, nx, ny, nx*size, ny*size, ny*size, 0.0_dp, kinds(rule), &
                                elastic_material(e_block, 0.2_dp, 0.0_dp), &
                                linear_joint(ratios(r)*e_block/size, ratios(r)*e_block/size), &
                                0.0_dp)
                model%fixed(:, 1:(nx + 1)*(ny + 1)) = .true.
                ! Rollers on the top block's sides: no free corners at the joint's ends.
                model%fixed(1, (nx + 1)*(ny + 1) + 1::nx + 1) = .true.
                model%fixed(1, (nx + 1)*(ny + 2)::nx + 1) = .true.
                model%load_sets(1)%pressures = [(pressure_load_t( &
                    element=2*nx*ny - nx + i, face=3, p1=20.0_dp + 160.0_dp*(i - 1)/nx, &
                    p2=20.0_dp + 160.0_dp*i/nx), i=1, nx)]
                model%stages(1) = stage_t(kind=stage_load, load_set=1, increments=1, &
                                          label='LOAD')
                call run_analysis(model, results, error)
                if (allocated(error)) return
                call profile(results, rule == 2, s, y)
                amp(rule, r) = zigzag(s, y)/100.0_dp
            end do
            write (*, '(a,es9.2,a,f8.4,a,f8.4,a)') '    linear traction, kn/(E/h) =', ratios(r), &
                ': zig-zag Gauss', 100*amp(1, r), ' %, Newton-Cotes', 100*amp(2, r), &
                ' % of the mean'
            call check(error, amp(2, r), 0.0_dp, 'Newton-Cotes zig-zag / mean', abs=0.01_dp)
            if (allocated(error)) return
        end do
    end subroutine test_oscillation

    !> Tractions of the consistent (Gauss) and lumped (Newton-Cotes) joint in the stiff
    !> limit, from the nodal forces f(0:n) that a bonded support takes along a line of n
    !> equal joints of length h. Both joints then pass on exactly these forces; Newton-Cotes
    !> lumps them, t_i = f_i / (tributary length); a 2-point Gauss joint integrates the
    !> linear traction exactly, f = M t with M = sum h/6 [2 1; 1 2] (the consistent "mass"
    !> matrix of the line), so its nodal tractions are M^-1 f and its stations the linear
    !> interpolation at xi = -+1/sqrt 3. M^-1 turns a force peaked at one node into
    !> tractions alternating in sign, decaying by 2 - sqrt 3 = 0.27 per node.
    subroutine stiff_limit(f, h, lumped, gauss)
        real(dp), intent(in) :: f(0:), h
        real(dp), intent(out) :: lumped(0:), gauss(:)
        real(dp), parameter :: g = 0.57735026918962576451_dp
        real(dp) :: diag(0:size(f) - 1), rhs(0:size(f) - 1), t(0:size(f) - 1), m
        integer :: i, n
        n = size(f) - 1
        lumped = f/h
        lumped([0, n]) = 2.0_dp*lumped([0, n])
        ! Thomas algorithm on M t = f (diagonal 4h/6, 2h/6 at the ends, off-diagonal h/6).
        diag = 4.0_dp*h/6.0_dp
        diag([0, n]) = 2.0_dp*h/6.0_dp
        rhs = f
        do i = 1, n
            m = (h/6.0_dp)/diag(i - 1)
            diag(i) = diag(i) - m*h/6.0_dp
            rhs(i) = rhs(i) - m*rhs(i - 1)
        end do
        t(n) = rhs(n)/diag(n)
        do i = n - 1, 0, -1
            t(i) = (rhs(i) - h/6.0_dp*t(i + 1))/diag(i)
        end do
        do i = 1, n
            gauss(2*i - 1) = 0.5_dp*((1.0_dp + g)*t(i - 1) + (1.0_dp - g)*t(i))
            gauss(2*i) = 0.5_dp*((1.0_dp - g)*t(i - 1) + (1.0_dp + g)*t(i))
        end do
    end subroutine stiff_limit

    !> Schellekens & de Borst's case (1993): a stiff joint ahead of a crack tip. Two blocks
    !> 20 x 4 (E = 1e4 kPa, nu = 0.2, elements 1 x 1), the bottom one fixed, the top one on
    !> rollers at its right side (a plane of symmetry) and pulled by 100 kPa on its top;
    !> joints only along the right half, so the left half is a crack, its tip at x = 10.
    !> The joint's kn = ks = kn_t (1e3 and 1e6 times E/h) gives it the same tangent open or
    !> closed, so the single increment is the linear solution; only the shear it reports is
    !> capped (zero in tension, Coulomb) and is not used here.
    !> Reference, independent of the joint element: the same blocks without joints, the top
    !> block's nodes along the right half fixed (bonded to the rigid base); the base
    !> reactions there (they sum to the 2000 kN/m applied, 1e-10) are the nodal forces that
    !> a stiff joint must pass on. Asserted:
    !> - Newton-Cotes: its tractions are those forces lumped (stiff_limit), to
    !>   10 E/(kn h) of the peak (the joint's compliance, O(E/(kn h)), is all that
    !>   separates it from the bonded blocks), and its zig-zag (zigzag) is below 1 % of the
    !>   mean traction on the joint (200 kPa), as the bonded reference's is;
    !> - Gauss: its stations are the consistent projection M^-1 f of the same forces
    !>   (stiff_limit), same tolerance, which zig-zags: above 10 % of the mean, ten times
    !>   Newton-Cotes' bound. Measured: Gauss 35 % at both ratios (its station 1.2 m ahead
    !>   of the tip reads -260 kPa, compression, where the lumped bonded tractions give
    !>   +430 kPa), Newton-Cotes 0.1 % (docs/theory.md section 12).
    subroutine test_notch_oscillation(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        integer, parameter :: nx = 20, ny = 4, crack = 10, nj = nx - crack
        real(dp), parameter :: e_block = 1.0e4_dp, h = 1.0_dp, pull = 100.0_dp, &
                               ratios(2) = [1.0e3_dp, 1.0e6_dp], mean = pull*nx/nj
        real(dp) :: force(0:nj), lumped(0:nj), gauss(2*nj), amp(2), dev(2), peak
        real(dp), allocatable :: s(:), y(:)
        integer :: r, rule, i, nb
        nb = (nx + 1)*(ny + 1)
        ! The bonded reference: no joints, the ligament's top-block nodes held.
        call notched_blocks(model, elem_joint_lobatto, 1.0_dp, nx + 1)
        model%fixed(:, nb + crack + 1:nb + nx + 1) = .true.
        call run_analysis(model, results, error)
        if (allocated(error)) return
        force = -results%stages(1)%reaction(2, nb + crack + 1:nb + nx + 1)
        call check(error, sum(force), pull*nx*h, 'bonded reactions = load', rel=1e-10_dp)
        if (allocated(error)) return
        call stiff_limit(force, h, lumped, gauss)
        peak = maxval(abs(lumped))
        amp(1) = zigzag([(crack*h + i*h, i=0, nj)], lumped)/mean
        write (*, '(a,f8.4,a)') '    notch, bonded reference: zig-zag', 100*amp(1), &
            ' % of the mean'
        call check(error, amp(1), 0.0_dp, 'bonded reference zig-zag / mean', abs=0.01_dp)
        if (allocated(error)) return
        do r = 1, 2
            do rule = 1, 2
                call notched_blocks(model, merge(elem_joint_gauss, elem_joint_lobatto, &
                                                 rule == 1), ratios(r), crack + 1)
                call run_analysis(model, results, error)
                if (allocated(error)) return
                call profile(results, rule == 2, s, y)
                amp(rule) = zigzag(s, y)/mean
                if (rule == 1) then
                    dev(rule) = maxval(abs(y - gauss))/peak
                else
                    dev(rule) = maxval(abs(y - lumped))/peak
                end if
            end do
            write (*, '(a,es8.1,a,2f8.4,a,2es8.1,a)') '    notch, kn/(E/h) =', ratios(r), &
                ': zig-zag Gauss, Newton-Cotes', 100*amp, ' % of the mean; from the limit', &
                dev, ' of the peak'
            call check(error, dev(1), 0.0_dp, 'Gauss = M^-1 f (bonded)', abs=10.0_dp/ratios(r))
            if (allocated(error)) return
            call check(error, dev(2), 0.0_dp, 'Newton-Cotes = lumped f (bonded)', &
                       abs=10.0_dp/ratios(r))
            if (allocated(error)) return
            call check(error, amp(2), 0.0_dp, 'Newton-Cotes zig-zag / mean', abs=0.01_dp)
            if (allocated(error)) return
            if (.not. amp(1) > 0.1_dp) then
                call fail(error, 'Gauss does not zig-zag ahead of the crack tip')
                return
            end if
        end do
    contains
        subroutine notched_blocks(model, kind, ratio, first)
            type(model_t), intent(out) :: model
            integer, intent(in) :: kind, first
            real(dp), intent(in) :: ratio
            call two_blocks(model, nx, ny, nx*h, ny*h, ny*h, 0.0_dp, kind, &
                            elastic_material(e_block, 0.2_dp, 0.0_dp), &
                            linear_joint(ratio*e_block/h, ratio*e_block/h), 0.0_dp, first)
            model%fixed(:, 1:nb) = .true.
            model%fixed(1, nb + nx + 1::nx + 1) = .true.
            model%load_sets(1)%pressures = [(pressure_load_t(element=2*nx*ny - nx + i, &
                                             face=3, p1=-pull, p2=-pull), i=1, nx)]
            model%stages(1) = stage_t(kind=stage_load, load_set=1, increments=1, label='PULL')
            ! One increment by design (the linear solution, above): no error control (issue
            ! 21), which would subdivide it, the Goodman law not being a linear one to it.
            model%error_tolerance = 0.0_dp
        end subroutine notched_blocks
    end subroutine test_notch_oscillation

    !> The thin layer as d -> 0 with E/d fixed tends to a joint with kn = E(1-nu)/((1+nu)
    !> (1-2nu) d) and ks = E/(2(1+nu) d), integrated like the layer's quads by 2-point
    !> Gauss: the same two blocks under a linearly varying pressure and a uniform shear on
    !> top, layer thickness d = 0.1, 0.01, 0.001 (width 4, so d/length = 0.25 to 0.0025).
    !> The largest difference of the top block's displacements from the joint model's,
    !> relative to the largest displacement, must fall with d (each step at least 5 times
    !> smaller) and be below 1e-3 at d = 0.001.
    subroutine test_thin_to_joint(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        integer, parameter :: nx = 4, ny = 2
        real(dp), parameter :: nu = 0.3_dp, e_over_d = 2.0e4_dp, thickness(3) = [0.1_dp, 0.01_dp, &
                                                                                 1.0e-3_dp]
        real(dp) :: kn, ks, diff(3)
        real(dp), allocatable :: u_joint(:, :)
        integer :: k, nb, i
        kn = e_over_d*(1.0_dp - nu)/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu))
        ks = e_over_d/(2.0_dp*(1.0_dp + nu))
        nb = (nx + 1)*(ny + 1)
        do k = 0, 3
            if (k == 0) then
                call two_blocks(model, nx, ny, 4.0_dp, 2.0_dp, 2.0_dp, 0.0_dp, &
                                elem_joint_gauss, elastic_material(1.0e5_dp, 0.25_dp, 0.0_dp), &
                                linear_joint(kn, ks), 0.0_dp)
            else
                call two_blocks(model, nx, ny, 4.0_dp, 2.0_dp, 2.0_dp, thickness(k), elem_quad4, &
                                elastic_material(1.0e5_dp, 0.25_dp, 0.0_dp), &
                                elastic_material(e_over_d*thickness(k), nu, 0.0_dp), 0.0_dp)
            end if
            model%fixed(:, 1:nx + 1) = .true.
            model%load_sets(1)%pressures = [(pressure_load_t(element=2*nx*ny - nx + i, face=3, &
                                             p1=100.0_dp + 50.0_dp*(i - 1), &
                                             p2=100.0_dp + 50.0_dp*i), i=1, nx)]
            call edge_traction(model, [(nb + ny*(nx + 1) + i, i=1, nx + 1)], &
                               [30.0_dp, 0.0_dp], model%load_sets(1)%nodal_force)
            model%stages(1) = stage_t(kind=stage_load, load_set=1, increments=1, label='LOAD')
            call run_analysis(model, results, error)
            if (allocated(error)) return
            associate (u => results%stages(1)%displacement(:, nb + 1:))
                if (k == 0) then
                    u_joint = u
                else
                    diff(k) = maxval(abs(u - u_joint))/maxval(abs(u_joint))
                end if
            end associate
        end do
        write (*, '(a,3es10.2)') '    thin layer vs joint, d = 0.1, 0.01, 0.001:', diff
        do k = 2, 3
            if (.not. diff(k) < diff(k - 1)/5.0_dp) then
                call fail(error, 'the thin layer does not approach the joint as d falls')
                return
            end if
        end do
        call check(error, diff(3), 0.0_dp, 'thin layer (d = 0.001) vs joint', abs=1.0e-3_dp)
    end subroutine test_thin_to_joint

    !> Opening of a phase from given stations (closed form): 4 Lobatto joints of length 1 on
    !> a line rising at 10 deg, opening du_n = 0.01 (s - 2.5) m along the line. The top is the
    !> line's end (s = 4); the open zone ends where du_n = open_gap, at s = 2.5 + 100 open_gap
    !> (linear, so the interpolation is exact): depth 1.5 - 100 open_gap, width 0.015 m.
    subroutine test_opening(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(interface_result_t) :: res
        type(opening_t), allocatable :: openings(:)
        real(dp) :: zero(4, 4, 12)
        integer :: k
        call two_blocks(model, 4, 1, 4.0_dp, 1.0_dp, 1.0_dp, 0.0_dp, elem_joint_lobatto, &
                        elastic_material(1.0e4_dp, 0.2_dp, 0.0_dp), linear_joint(1.0e6_dp, &
                        1.0e4_dp), 10.0_dp)
        zero = 0.0_dp
        call interface_stations(model, zero, zero, [(.true., k=1, 12)], res)
        res%du_n = 0.01_dp*(res%s - 2.5_dp)
        call phase_openings(model, res, openings)
        if (size(openings) /= 1) then
            call fail(error, 'expected one phase')
            return
        end if
        call check(error, openings(1)%depth, 1.5_dp - 100.0_dp*open_gap, 'depth', rel=1e-12_dp)
        if (allocated(error)) return
        call check(error, openings(1)%width, 0.015_dp, 'width', rel=1e-12_dp)
        if (allocated(error)) return
        call check(error, openings(1)%length, 4.0_dp, 'length', rel=1e-12_dp)
    end subroutine test_opening

    !> Slab sections from a given stress field (closed form): a strip of 3 x 2 quads, length
    !> 12, thickness h = 0.6 (two layers), its axis t at 35 deg, with sigma_tt = a + b zeta
    !> (zeta across the strip from its mid-line along n) and tau = c: N = a h, V = c h,
    !> M = b h^3/12 in every section (2x2 Gauss integrates the quadratic moment exactly),
    !> fibre stresses a +- b h/2; 1e-12 relative.
    subroutine test_slab_sections(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(slab_result_t) :: res
        real(dp), parameter :: a = -3000.0_dp, b = 2000.0_dp, c = 150.0_dp, h = 0.6_dp
        real(dp) :: x(2, 12), t(2), n(2), stress(4, 4, 6), xg(2, 4), zeta, sig_t, sxx, syy, &
                    sxy, p(2)
        integer :: conn(4, 6), i, j, e, ig
        t = [cos(35.0_dp*deg), sin(35.0_dp*deg)]
        n = [-t(2), t(1)]
        do j = 0, 2
            do i = 0, 3
                p = 4.0_dp*i*t + (h*j/2.0_dp - h/2.0_dp)*n
                x(:, 4*j + i + 1) = p
            end do
        end do
        e = 0
        do j = 0, 1
            do i = 0, 2
                e = e + 1
                conn(:, e) = [4*j + i + 1, 4*j + i + 2, 4*(j + 1) + i + 2, 4*(j + 1) + i + 1]
            end do
        end do
        call new_model(model, x, conn, [(1, i=1, 6)], [elastic_material(3.0e7_dp, 0.2_dp, &
                       0.0_dp)])
        model%mesh%group = 1
        model%mesh%group_name = [character(len=10) :: 'SLAB']
        model%slab_groups = [1]
        allocate (model%interfaces(0))
        stress = 0.0_dp
        do e = 1, 6
            ! Gauss points of the quad (2x2 rule, point k nearest node k).
            do ig = 1, 4
                xg(:, ig) = 0.0_dp
                do i = 1, 4
                    xg(:, ig) = xg(:, ig) + 0.25_dp*(1.0_dp + gx(i)*gx(ig)/sqrt(3.0_dp))* &
                                (1.0_dp + gy(i)*gy(ig)/sqrt(3.0_dp))*x(:, conn(i, e))
                end do
                zeta = dot_product(xg(:, ig), n)
                sig_t = a + b*zeta
                sxx = sig_t*t(1)**2 + 2.0_dp*c*t(1)*n(1)
                syy = sig_t*t(2)**2 + 2.0_dp*c*t(2)*n(2)
                sxy = sig_t*t(1)*t(2) + c*(t(1)*n(2) + t(2)*n(1))
                stress(:, ig, e) = [sxx, syy, 0.0_dp, sxy]
            end do
        end do
        call slab_stresses(model, stress, [(.true., i=1, 6)], res)
        if (size(res%axial) /= 3) then
            call fail(error, 'expected 3 sections')
            return
        end if
        do j = 1, 3
            call check(error, res%thickness(j), h, 'thickness', rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, res%axial(j), a*h, 'N = a h', rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, res%shear(j), c*h, 'V = c h', rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, res%moment(j), b*h**3/12.0_dp, 'M = b h^3/12', rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, res%sigma_water(j), a + b*h/2.0_dp, 'water-side fibre', rel=1e-12_dp)
            if (allocated(error)) return
        end do
    contains
        pure real(dp) function gx(k)
            integer, intent(in) :: k
            gx = merge(-1.0_dp, 1.0_dp, k == 1 .or. k == 4)
        end function gx
        pure real(dp) function gy(k)
            integer, intent(in) :: k
            gy = merge(-1.0_dp, 1.0_dp, k <= 2)
        end function gy
    end subroutine test_slab_sections
end module test_analysis_interface
