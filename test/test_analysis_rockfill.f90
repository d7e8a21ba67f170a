!> The E-B rockfill law through the finite-element analysis: a drained triaxial test on an
!> axisymmetric element (cell pressure, then the deviator in stages at constant sigma3)
!> against Kondner's hyperbola, the unload-reload slope, and the convergence rates of the
!> midpoint and forward Euler increments (docs/theory.md sections 8 and 9).
module test_analysis_rockfill
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_model, only: model_t, material_t, load_set_t, pressure_load_t, stage_t, &
                          stage_load, stage_reset, axisymmetric, law_duncan_eb, &
                          solver_midpoint, solver_euler, solver_newton
    use cfrd_results, only: results_t, stage_result_t
    use cfrd_linear_static, only: solve_linear_static
    use cfrd_duncan_eb, only: eb_params_t, eb_initial_modulus, eb_failure_deviator, &
                              eb_unload_modulus, nu_t_max, eb_tangent, eb_state_t, &
                              eb_stress_state, eb_moduli_gradient
    use cfrd_material_law, only: eb_parameters, material_update, material_update_tangent, &
                                 material_update_with_tangent, &
                                 update_substeps, max_substeps
    use cfrd_test_models, only: new_model, elastic_material
    use cfrd_model, only: plane_strain
    implicit none
    private

    public :: collect_analysis_rockfill

    real(dp), parameter :: pa = 101.325_dp, radius = 0.05_dp, height = 0.1_dp

    !> Table 3 of the paper (../shared/reference/tianshengqiao-i.md): phi0, dphi, K, n, Rf,
    !> Kb, m for IIA, IIIA, IIIB, IIID, IIIC; c = 0, Kur = 2 K.
    real(dp), parameter :: table3(7, 5) = reshape([ &
                                                  50.6_dp, 7.0_dp, 1000.0_dp, 0.35_dp, 0.71_dp, 450.0_dp, 0.24_dp, &
                                                  52.5_dp, 8.0_dp, 900.0_dp, 0.36_dp, 0.76_dp, 400.0_dp, 0.19_dp, &
                                                  51.0_dp, 13.0_dp, 564.0_dp, 0.35_dp, 0.85_dp, 204.0_dp, 0.18_dp, &
                                                  51.0_dp, 13.5_dp, 432.0_dp, 0.30_dp, 0.80_dp, 300.0_dp, -0.18_dp, &
                                                  45.0_dp, 10.0_dp, 250.0_dp, 0.25_dp, 0.73_dp, 125.0_dp, 0.00_dp], &
                                                  [7, 5])
    character(len=4), parameter :: zone(5) = ['IIA ', 'IIIA', 'IIIB', 'IIID', 'IIIC']

contains

    subroutine collect_analysis_rockfill(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('triaxial_kondner_hyperbola', test_kondner), &
                new_unittest('triaxial_volumetric_strain', test_volumetric), &
                new_unittest('unload_reload_slope', test_unload_reload), &
                new_unittest('midpoint_second_order_euler_first', test_rates), &
                new_unittest('newton_triaxial_with_unloading', test_newton), &
                new_unittest('eb_consistent_tangent', test_eb_tangent), &
                new_unittest('newton_quadratic_rate', test_newton_rate), &
                new_unittest('newton_gmres_corrections', test_newton_gmres), &
                new_unittest('substep_update_kondner', test_substep_update), &
                new_unittest('substep_consistent_tangent', test_substep_tangent), &
                new_unittest('update_with_tangent_one_pass', test_update_with_tangent), &
                new_unittest('error_control_one_increment', test_error_control) &
                ]
    end subroutine collect_analysis_rockfill

    pure function table3_material(i) result(mat)
        integer, intent(in) :: i
        type(material_t) :: mat
        mat%law = law_duncan_eb
        mat%label = zone(i)
        mat%phi0 = table3(1, i)
        mat%dphi = table3(2, i)
        mat%k_modulus = table3(3, i)
        mat%n_exponent = table3(4, i)
        mat%failure_ratio = table3(5, i)
        mat%k_bulk = table3(6, i)
        mat%m_exponent = table3(7, i)
        mat%k_unload = 2.0_dp*table3(3, i)
        mat%sigma3_floor = 0.1_dp*pa
    end function table3_material

    !> One axisymmetric element (radius 0.05 m, height 0.1 m; axis and base on rollers).
    !> Load set 1: the cell pressure p3 on the side and the top; set 2: a deviator step dq on
    !> the top. Stages: set 1 in `ncell` increments, RESET, then `steps` times set 2 in `ninc`
    !> increments each (one result per deviator step).
    subroutine triaxial(mat, p3, dq, steps, ninc, solver, eps1, epsv, error, unload_steps, &
                        errtol, residual, increments, work)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: p3, dq
        integer, intent(in) :: steps, ninc, solver
        real(dp), allocatable, intent(out) :: eps1(:), epsv(:)
        type(error_t), allocatable, intent(out) :: error
        integer, intent(in), optional :: unload_steps   !! then this many steps of -dq
        !> midpoint / Euler error control: ERRTOL (0: none; absent: the default)
        real(dp), intent(in), optional :: errtol
        !> the largest relative residual and the increments accepted of the deviator stages
        real(dp), intent(out), optional :: residual
        integer, intent(out), optional :: increments
        !> of the deviator stages: Newton iterations and numeric factorisations
        integer, intent(out), optional :: work(2)
        type(model_t) :: model
        type(results_t) :: results
        integer :: s, nunload, ncell
        nunload = 0
        if (present(unload_steps)) nunload = unload_steps
        ncell = 400
        call new_model(model, reshape([0.0_dp, 0.0_dp, radius, 0.0_dp, radius, height, &
                                       0.0_dp, height], [2, 4]), &
                       reshape([1, 2, 3, 4], [4, 1]), [1], [mat])
        model%analysis = axisymmetric
        model%pa = pa
        model%solver = solver
        model%tolerance = 1.0e-11_dp
        if (present(errtol)) model%error_tolerance = errtol
        model%fixed(1, [1, 4]) = .true.
        model%fixed(2, [1, 2]) = .true.
        deallocate (model%load_sets, model%stages)
        allocate (model%load_sets(3), model%stages(2 + steps + nunload))
        do s = 1, 3
            allocate (model%load_sets(s)%nodal_force(2, 4), source=0.0_dp)
            allocate (model%load_sets(s)%gravity(0))
        end do
        model%load_sets(1)%pressures = [pressure_load_t(1, 2, p3, p3), &
                                        pressure_load_t(1, 3, p3, p3)]
        model%load_sets(2)%pressures = [pressure_load_t(1, 3, dq, dq)]
        model%load_sets(3)%pressures = [pressure_load_t(1, 3, -dq, -dq)]
        model%stages(1) = stage_t(kind=stage_load, load_set=1, increments=ncell, label='CELL')
        model%stages(2) = stage_t(kind=stage_reset, label='RESET')
        do s = 1, steps
            model%stages(2 + s) = stage_t(kind=stage_load, load_set=2, increments=ninc, &
                                          label='SHEAR')
        end do
        do s = 1, nunload
            model%stages(2 + steps + s) = stage_t(kind=stage_load, load_set=3, &
                                                  increments=ninc, label='UNLOAD')
        end do
        call solve_linear_static(model, results, error)
        if (allocated(error)) return
        allocate (eps1(steps + nunload), epsv(steps + nunload))
        if (present(residual)) residual = maxval(results%stages(3:)%max_residual)
        if (present(increments)) increments = sum(results%stages(3:)%increments)
        if (present(work)) work = [sum(results%stages(3:)%iterations), &
                                   sum(results%stages(3:)%factorisations)]
        do s = 1, steps + nunload
            associate (u => results%stages(2 + s)%displacement)
                ! Compression positive: eps1 = -u_z(top)/H, eps_v = eps1 - 2 u_r(side)/R.
                eps1(s) = -u(2, 3)/height
                epsv(s) = eps1(s) - 2.0_dp*u(1, 3)/radius
            end associate
        end do
    end subroutine triaxial

    !> With sigma3 constant, d eps1 = dq / Et exactly (isotropic tangent, dsigma_r = 0), so
    !> eps1 follows Kondner's hyperbola eps1 = q / (Ei (1 - Rf q / qf)) (Duncan & Chang 1970).
    !> Every Table 3 material at 100, 500 and 1500 kPa, q in steps of 0.1 qf to 0.9 qf, 40
    !> midpoint increments per step: 0.2 % (issue 4).
    subroutine test_kondner(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: cell(3) = [100.0_dp, 500.0_dp, 1500.0_dp]
        real(dp), allocatable :: eps1(:), epsv(:)
        type(eb_params_t) :: p
        real(dp) :: qf, ei, q, exact
        integer :: i, c, s
        character(len=60) :: what
        do i = 1, 5
            p = eb_parameters(table3_material(i), pa)
            do c = 1, 3
                qf = eb_failure_deviator(p, cell(c))
                ei = eb_initial_modulus(p, cell(c))
                call triaxial(table3_material(i), cell(c), 0.1_dp*qf, 9, 40, solver_midpoint, &
                              eps1, epsv, error)
                if (allocated(error)) return
                do s = 1, 9
                    q = 0.1_dp*qf*s
                    exact = q/(ei*(1.0_dp - p%rf*q/qf))
                    write (what, '(a,a,f7.1,a,f4.1,a)') trim(zone(i)), ' at ', cell(c), &
                        ' kPa, q = ', 0.1_dp*s, ' qf: eps1'
                    call check(error, eps1(s), exact, trim(what), rel=2.0e-3_dp)
                    if (allocated(error)) return
                end do
            end do
        end do
    end subroutine test_kondner

    !> eps_v: d eps_v = dp / Bt with dp = dq/3 at constant sigma3, Bt = Kb pa (s3/pa)^m
    !> bounded below by Et/3 (nu_t >= 0). Where Et(q) > 3 Bt the bound holds and
    !> d eps_v = dq/Et; it stops holding at q* = (qf/Rf)(1 - sqrt(3 Bt/Ei)). Hence
    !> eps_v(q) = H(min(q, q*)) + max(q - q*, 0)/(3 Bt), H(x) = x/(Ei (1 - Rf x/qf)).
    !> The upper bound (nu_t <= 0.49) must stay inactive on the path: checked below.
    subroutine test_volumetric(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: cell(3) = [100.0_dp, 500.0_dp, 1500.0_dp]
        real(dp), allocatable :: eps1(:), epsv(:)
        type(eb_params_t) :: p
        real(dp) :: qf, ei, bt, qstar, q, exact, et_min
        integer :: i, c, s
        character(len=60) :: what
        do i = 1, 5
            p = eb_parameters(table3_material(i), pa)
            do c = 1, 3
                qf = eb_failure_deviator(p, cell(c))
                ei = eb_initial_modulus(p, cell(c))
                bt = p%kb*pa*(cell(c)/pa)**p%m
                et_min = ei*(1.0_dp - p%rf*0.9_dp)**2
                call check(error, et_min > 3.0_dp*(1.0_dp - 2.0_dp*nu_t_max)*bt, &
                           'upper Bt bound inactive on the path')
                if (allocated(error)) return
                qstar = 0.0_dp
                if (3.0_dp*bt < ei) qstar = qf/p%rf*(1.0_dp - sqrt(3.0_dp*bt/ei))
                call triaxial(table3_material(i), cell(c), 0.1_dp*qf, 9, 40, solver_midpoint, &
                              eps1, epsv, error)
                if (allocated(error)) return
                do s = 1, 9
                    q = 0.1_dp*qf*s
                    exact = hyperbola(min(q, qstar)) + max(q - qstar, 0.0_dp)/(3.0_dp*bt)
                    write (what, '(a,a,f7.1,a,f4.1,a)') trim(zone(i)), ' at ', cell(c), &
                        ' kPa, q = ', 0.1_dp*s, ' qf: eps_v'
                    call check(error, epsv(s), exact, trim(what), rel=2.0e-3_dp)
                    if (allocated(error)) return
                end do
            end do
        end do
    contains
        pure real(dp) function hyperbola(x)
            real(dp), intent(in) :: x
            hyperbola = x/(ei*(1.0_dp - p%rf*x/qf))
        end function hyperbola
    end subroutine test_volumetric

    !> Load IIIB at 500 kPa to q = 0.8 qf, then unload in three steps of 0.2 qf: below 0.75
    !> of the past maximum of the stress-state function (q < 0.6 qf at constant sigma3) the
    !> tangent is Eur = Kur pa (sigma3/pa)^n (Duncan et al. 1980), so the slope dq/d eps1 of
    !> the third step is Eur, exactly, since sigma3 stays constant (the second step, also
    !> linear, absorbs the out-of-balance force the transition left).
    subroutine test_unload_reload(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: eps1(:), epsv(:)
        type(eb_params_t) :: p
        real(dp) :: qf, slope
        p = eb_parameters(table3_material(3), pa)
        qf = eb_failure_deviator(p, 500.0_dp)
        call triaxial(table3_material(3), 500.0_dp, 0.2_dp*qf, 4, 20, solver_midpoint, eps1, &
                      epsv, error, unload_steps=3)
        if (allocated(error)) return
        slope = -0.2_dp*qf/(eps1(7) - eps1(6))
        ! Exact up to the out-of-balance force the midpoint increments leave (about 1e-6 of
        ! the load here): 1e-5.
        call check(error, slope, eb_unload_modulus(p, 500.0_dp), 'unloading slope', &
                   rel=1.0e-5_dp)
    end subroutine test_unload_reload

    !> IIIB at 500 kPa loaded to 0.8 qf with 1, 2, ..., 64 increments: the error of eps1
    !> against 1024 midpoint increments falls as h^2 for the midpoint rule and as h for
    !> forward Euler (docs/theory.md section 9; the table is in docs/performance.md). The
    !> asymptotic rate shows from 16 increments on (the same scheme on the 1D hyperbola gives
    !> 1.73 and 1.86 over the last two halvings), so the rates are taken from 16, 32, 64.
    subroutine test_rates(error)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: nk = 7
        real(dp), allocatable :: eps1(:), epsv(:)
        type(eb_params_t) :: p
        real(dp) :: qf, reference, err_mid(nk), err_euler(nk), rate
        integer :: k
        p = eb_parameters(table3_material(3), pa)
        qf = eb_failure_deviator(p, 500.0_dp)
        call triaxial(table3_material(3), 500.0_dp, 0.8_dp*qf, 1, 1024, solver_midpoint, &
                      eps1, epsv, error, errtol=0.0_dp)
        if (allocated(error)) return
        reference = eps1(1)
        do k = 1, nk
            call triaxial(table3_material(3), 500.0_dp, 0.8_dp*qf, 1, 2**(k - 1), &
                          solver_midpoint, eps1, epsv, error, errtol=0.0_dp)
            if (allocated(error)) return
            err_mid(k) = abs(eps1(1) - reference)
            call triaxial(table3_material(3), 500.0_dp, 0.8_dp*qf, 1, 2**(k - 1), &
                          solver_euler, eps1, epsv, error, errtol=0.0_dp)
            if (allocated(error)) return
            err_euler(k) = abs(eps1(1) - reference)
        end do
        do k = 1, nk
            write (*, '(a,i3,a,es10.3,a,es10.3)') '  increments', 2**(k - 1), &
                ': error midpoint', err_mid(k)/reference, ', Euler', err_euler(k)/reference
        end do
        do k = nk - 1, nk
            rate = log(err_mid(k - 1)/err_mid(k))/log(2.0_dp)
            call check(error, rate, 2.0_dp, 'midpoint rate', abs=0.3_dp)
            if (allocated(error)) return
            rate = log(err_euler(k - 1)/err_euler(k))/log(2.0_dp)
            call check(error, rate, 1.0_dp, 'Euler rate', abs=0.15_dp)
            if (allocated(error)) return
        end do
    end subroutine test_rates

    !> Error control of the midpoint and Euler increments (docs/theory.md section 9, "Error
    !> control"): the triaxial test of IIIB at 500 kPa loaded from the isotropic state to
    !> q = 0.8 qf in ONE increment, against Kondner's hyperbola (closed form, as above).
    !> Without control (ERRTOL = 0) the one increment is accepted and eps1 is far off
    !> (midpoint: 64 % out of balance; Euler: in balance by construction, its error shows in
    !> the midpoint update's residual); with ERRTOL = 0.005 the increment is halved until
    !> every accepted increment's measure is below ERRTOL, and eps1 is within the order of
    !> the tolerance:
    !> at constant sigma3 a relative error e of the axial stress reached moves eps1 by about
    !> e q / Et = e (1 - Rf S)^-1 times its secant share, 1/(1 - 0.85 * 0.8) = 3.1 at
    !> S = 0.8, so 4 ERRTOL is the bound asserted.
    subroutine test_error_control(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: errtol = 5.0e-3_dp
        real(dp), allocatable :: eps1(:), epsv(:)
        type(eb_params_t) :: p
        real(dp) :: qf, ei, q, exact, residual, off
        integer :: solver, increments
        p = eb_parameters(table3_material(3), pa)
        qf = eb_failure_deviator(p, 500.0_dp)
        ei = eb_initial_modulus(p, 500.0_dp)
        q = 0.8_dp*qf
        exact = q/(ei*(1.0_dp - p%rf*q/qf))
        do solver = solver_midpoint, solver_euler
            call triaxial(table3_material(3), 500.0_dp, q, 1, 1, solver, eps1, epsv, error, &
                          errtol=0.0_dp, residual=residual, increments=increments)
            if (allocated(error)) return
            off = abs(eps1(1)/exact - 1.0_dp)
            write (*, '(a,i2,a,es10.3,a,es10.3,a,i5)') '  solver', solver, &
                ', no control: eps1 off by', off, ', residual', residual, ', increments', &
                increments
            call check(error, off > 10.0_dp*errtol, &
                       'without control the one increment should be far off')
            if (allocated(error)) return
            call triaxial(table3_material(3), 500.0_dp, q, 1, 1, solver, eps1, epsv, error, &
                          errtol=errtol, residual=residual, increments=increments)
            if (allocated(error)) return
            off = abs(eps1(1)/exact - 1.0_dp)
            write (*, '(a,i2,a,es10.3,a,es10.3,a,i5)') '  solver', solver, &
                ', ERRTOL 0.005: eps1 off by', off, ', residual', residual, ', increments', &
                increments
            call check(error, residual <= errtol, 'a residual above ERRTOL was accepted')
            if (allocated(error)) return
            call check(error, eps1(1), exact, 'eps1 with error control', rel=4.0_dp*errtol)
            if (allocated(error)) return
        end do
    end subroutine test_error_control

    !> Newton iterations (consistent tangent, tolerance 1e-11) on the triaxial test of IIIB at
    !> 500 kPa: the loading branch follows Kondner's hyperbola to 0.2 % and, after unloading
    !> below 0.75 of the past stress state, the slope is Eur (closed forms as above).
    subroutine test_newton(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: eps1(:), epsv(:)
        type(eb_params_t) :: p
        real(dp) :: qf, ei
        p = eb_parameters(table3_material(3), pa)
        qf = eb_failure_deviator(p, 500.0_dp)
        ei = eb_initial_modulus(p, 500.0_dp)
        call triaxial(table3_material(3), 500.0_dp, 0.2_dp*qf, 4, 40, solver_newton, eps1, &
                      epsv, error, unload_steps=3)
        if (allocated(error)) return
        call check_kondner(eps1(1:4), p, qf, ei, error)
        if (allocated(error)) return
        call check(error, -0.2_dp*qf/(eps1(7) - eps1(6)), eb_unload_modulus(p, 500.0_dp), &
                   'Newton: unloading slope', rel=1.0e-5_dp)
    end subroutine test_newton

    !> Newton's tangent of the E-B midpoint update (cfrd_material_law:
    !> material_update_tangent, docs/theory.md section 9) against central differences of the
    !> update itself, at points inside every branch of the law (away from the kinks, where
    !> the update is smooth): loading with the Poisson bounds inactive (and a cohesion),
    !> the stress-level cap, the sigma3 floor, each Poisson bound, the friction-angle clamp,
    !> the unloading transition and full unloading, Eur below the loading modulus, and an
    !> axisymmetric increment with hoop strain. Each case first asserts that its half-way
    !> stress lies in the branch it is named for. 1e-6 of the largest entry.
    subroutine test_eb_tangent(error)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: ncase = 10
        character(len=*), parameter :: names(ncase) = [character(len=28) :: &
            'loading, cohesion', 'stress-level cap', 'sigma3 floor', 'Poisson lower bound', &
            'Poisson upper bound', 'friction-angle clamp', 'unloading transition', &
            'unloading (Eur)', 'Eur below Et', 'axisymmetric increment']
        real(dp), parameter :: s0(4, ncase) = reshape([ &
            -300.0_dp, -700.0_dp, -300.0_dp, 50.0_dp, &
            -100.0_dp, -900.0_dp, -150.0_dp, 20.0_dp, &
            5.0_dp, -60.0_dp, -10.0_dp, 3.0_dp, &
            -500.0_dp, -620.0_dp, -520.0_dp, 10.0_dp, &
            -300.0_dp, -700.0_dp, -300.0_dp, 40.0_dp, &
            -60.0_dp, -200.0_dp, -80.0_dp, 10.0_dp, &
            -400.0_dp, -900.0_dp, -450.0_dp, 60.0_dp, &
            -400.0_dp, -900.0_dp, -450.0_dp, 60.0_dp, &
            -400.0_dp, -900.0_dp, -450.0_dp, 60.0_dp, &
            -300.0_dp, -700.0_dp, -300.0_dp, 50.0_dp], [4, ncase])
        real(dp), parameter :: de0(4, ncase) = reshape([ &
            -1.0e-4_dp, -3.0e-4_dp, 0.0_dp, 2.0e-4_dp, &
            -1.0e-4_dp, -4.0e-4_dp, 0.0_dp, 1.0e-4_dp, &
            1.0e-4_dp, -3.0e-4_dp, 0.0_dp, 1.0e-4_dp, &
            -1.0e-4_dp, -2.0e-4_dp, 0.0_dp, 1.0e-4_dp, &
            -1.0e-4_dp, -3.0e-4_dp, 0.0_dp, 2.0e-4_dp, &
            -1.0e-4_dp, -3.0e-4_dp, 0.0_dp, 1.0e-4_dp, &
            -1.0e-5_dp, 2.0e-5_dp, 0.0_dp, -1.0e-5_dp, &
            -1.0e-5_dp, 2.0e-5_dp, 0.0_dp, -1.0e-5_dp, &
            -1.0e-5_dp, 2.0e-5_dp, 0.0_dp, -1.0e-5_dp, &
            -1.0e-4_dp, -3.0e-4_dp, -0.5e-4_dp, 2.0e-4_dp], [4, ncase])
        type(material_t) :: mat
        type(eb_params_t) :: p
        type(eb_state_t) :: st
        real(dp) :: history(2), c(4, 4), fd(4, 4), plus(4), minus(4), mid(4), de(4), h
        real(dp) :: d(4, 4), ss, et, bt, det(4), dbt(4)
        logical :: in_branch
        integer :: k, j
        do k = 1, ncase
            mat = table3_material(3)
            history = 0.0_dp
            select case (k)
            case (1)
                mat%cohesion = 20.0_dp
            case (5)
                mat%k_bulk = 20000.0_dp
            case (6)
                mat%phi0 = 88.0_dp
                mat%dphi = 10.0_dp
            case (7, 8, 9)
                if (k == 9) mat%k_unload = 0.5_dp*mat%k_modulus
                ss = eb_stress_state(eb_parameters(mat, pa), s0(:, k))
                history(1) = ss/merge(0.5_dp, 0.9_dp, k == 8)
            end select
            p = eb_parameters(mat, pa)
            call material_update(mat, pa, s0(:, k), [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
                                 history, de0(:, k), .true., plus, mid)
            call eb_tangent(p, mid, history(1), d, st)
            ss = eb_stress_state(p, mid)
            select case (k)
            case (1, 10)
                in_branch = st%level > 0.0_dp .and. st%level < p%level_cap .and. &
                            st%sigma3 > p%sigma3_floor .and. st%nu_t > 0.0_dp .and. &
                            st%nu_t < nu_t_max .and. .not. st%unloading
            case (2)
                in_branch = st%level == p%level_cap .and. st%sigma3 > p%sigma3_floor
            case (3)
                in_branch = st%sigma3 < p%sigma3_floor .and. st%level < p%level_cap
            case (4)
                in_branch = st%nu_t == 0.0_dp .and. st%sigma3 > p%sigma3_floor
            case (5)
                in_branch = abs(st%nu_t - nu_t_max) < 1.0e-14_dp
            case (6)
                in_branch = st%phi == 89.0_dp .and. st%sigma3 > p%sigma3_floor
            case (7)
                in_branch = ss < history(1) .and. ss > 0.75_dp*history(1)
            case (8)
                in_branch = ss < 0.75_dp*history(1)
            case (9)
                in_branch = st%unloading .and. eb_unload_modulus(p, st%sigma3) < st%et
            end select
            call check(error, in_branch, 'E-B tangent case '//trim(names(k))// &
                       ': the half-way stress is not in its branch')
            if (allocated(error)) return
            ! the moduli of the gradient routine are those of eb_tangent
            call eb_moduli_gradient(p, mid, history(1), et, bt, det, dbt)
            call check(error, et, st%et, 'E-B tangent case '//trim(names(k))//': Et', &
                       rel=1.0e-13_dp)
            if (allocated(error)) return
            call check(error, bt, st%bt, 'E-B tangent case '//trim(names(k))//': Bt', &
                       rel=1.0e-13_dp)
            if (allocated(error)) return
            call material_update_tangent(mat, pa, s0(:, k), [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
                                         history, de0(:, k), c)
            h = 1.0e-4_dp*maxval(abs(de0(:, k)))
            do j = 1, 4
                de = de0(:, k)
                de(j) = de(j) + h
                call material_update(mat, pa, s0(:, k), [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
                                     history, de, .true., plus, mid)
                de(j) = de(j) - 2.0_dp*h
                call material_update(mat, pa, s0(:, k), [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
                                     history, de, .true., minus, mid)
                fd(:, j) = (plus - minus)/(2.0_dp*h)
            end do
            call check(error, maxval(abs(c - fd)) <= 1.0e-6_dp*maxval(abs(fd)), &
                       'E-B tangent, '//trim(names(k))//': analytic and central '// &
                       'differences differ')
            if (allocated(error)) return
            ! the change of the moduli along the increment matters: C is not D(sigma_mid)
            call check(error, maxval(abs(c - d)) > 1.0e-4_dp*maxval(abs(fd)), &
                       'E-B tangent, '//trim(names(k))//': C equals D(sigma_mid)')
            if (allocated(error)) return
        end do
    end subroutine test_eb_tangent

    !> The rate of Newton's iterations where the law is smooth: a 3 x 3 block of IIIB (unit
    !> quads, plane strain; base fixed, left side on rollers) under 300 kPa on the top and
    !> 150 kPa on the right side (stage 1, 10 increments), then a top pressure rising from 0
    !> on the left to 400 kPa on the right in one increment (stage 2): every Gauss point
    !> stays inside one branch of the law (loading, below the cap, above the sigma3 floor,
    !> Poisson bounds inactive: asserted at the start and the end of stage 2), so that with
    !> the exact tangent of the update Newton converges quadratically (Newton-Kantorovich):
    !> the order log(r_k+1 / r_k) / log(r_k / r_k-1) of every step above round-off is 2,
    !> asserted >= 1.8 (measured: 1.90, 1.99; with D(sigma_mid) in place of the consistent
    !> tangent the order is 1).
    subroutine test_newton_rate(error)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: n = 3
        type(model_t) :: model
        type(results_t) :: results
        real(dp), allocatable :: x(:, :), r(:)
        integer, allocatable :: conn(:, :)
        type(eb_params_t) :: p
        real(dp) :: order
        integer :: i, j, e, s, k, used
        allocate (x(2, (n + 1)**2), conn(4, n*n))
        do j = 0, n
            do i = 0, n
                x(:, j*(n + 1) + i + 1) = [real(i, dp), real(j, dp)]
            end do
        end do
        do j = 0, n - 1
            do i = 0, n - 1
                conn(:, j*n + i + 1) = [j*(n + 1) + i + 1, j*(n + 1) + i + 2, &
                                        (j + 1)*(n + 1) + i + 2, (j + 1)*(n + 1) + i + 1]
            end do
        end do
        call new_model(model, x, conn, [(1, e=1, n*n)], [table3_material(3)])
        model%analysis = plane_strain
        model%pa = pa
        model%solver = solver_newton
        model%tolerance = 1.0e-14_dp
        model%max_iterations = 20
        model%fixed(:, 1:n + 1) = .true.
        model%fixed(1, 1:(n + 1)**2:n + 1) = .true.
        deallocate (model%load_sets, model%stages)
        allocate (model%load_sets(2))
        do s = 1, 2
            allocate (model%load_sets(s)%nodal_force(2, model%mesh%nnode), source=0.0_dp)
            allocate (model%load_sets(s)%gravity(0))
        end do
        model%load_sets(1)%pressures = [(pressure_load_t(n*(n - 1) + i, 3, 300.0_dp, &
                                                         300.0_dp), i=1, n), &
                                        (pressure_load_t(n*i, 2, 150.0_dp, 150.0_dp), i=1, n)]
        model%load_sets(2)%pressures = [(pressure_load_t(n*(n - 1) + i, 3, 400.0_dp*i/n, &
                                                         400.0_dp*(i - 1)/n), i=1, n)]
        model%stages = [stage_t(kind=stage_load, load_set=1, increments=10, label='CONFINE'), &
                        stage_t(kind=stage_load, load_set=2, increments=1, label='TILT')]
        call solve_linear_static(model, results, error)
        if (allocated(error)) return
        p = eb_parameters(table3_material(3), pa)
        do s = 1, 2
            call check(error, smooth_branch(results%stages(s)), 'stage '//merge('1', '2', &
                       s == 1)//': a Gauss point is not inside the loading branch')
            if (allocated(error)) return
        end do
        r = results%stages(2)%newton_residuals
        call check(error, size(r) >= 4, 'too few Newton iterations to see a rate')
        if (allocated(error)) return
        used = 0
        do k = 2, size(r) - 1
            if (r(k + 1) < 1.0e-13_dp) exit
            order = log(r(k + 1)/r(k))/log(r(k)/r(k - 1))
            write (*, '(a,3es10.2,a,f6.2)') '  residuals', r(k - 1:k + 1), ': order', order
            call check(error, order >= 1.8_dp, 'Newton is not quadratic on the smooth law: '// &
                       'order of the step to iteration '//achar(48 + k))
            if (allocated(error)) return
            used = used + 1
        end do
        call check(error, used >= 1, 'no step above round-off to measure the order on')
    contains
        !> Loading, 0 < S < cap, sigma3 above the floor and 0 < nu_t < 0.49 at every point.
        logical function smooth_branch(stage) result(inside)
            type(stage_result_t), intent(in) :: stage
            type(eb_state_t) :: st
            real(dp) :: d(4, 4)
            integer :: ee, ig
            inside = .true.
            do ee = 1, n*n
                do ig = 1, 4
                    call eb_tangent(p, stage%stress_gauss(:, ig, ee), &
                                    stage%history_gauss(1, ig, ee), d, st)
                    inside = inside .and. st%level > 0.0_dp .and. st%level < p%level_cap &
                             .and. st%sigma3 > p%sigma3_floor .and. st%nu_t > 0.0_dp .and. &
                             st%nu_t < nu_t_max .and. .not. st%unloading
                end do
            end do
        end function smooth_branch
    end subroutine test_newton_rate
    !> eps1 after deviator steps of 0.2 qf against Kondner's hyperbola (closed form, as
    !> test_kondner), to 0.2 %.
    subroutine check_kondner(eps1, p, qf, ei, error)
        real(dp), intent(in) :: eps1(:), qf, ei
        type(eb_params_t), intent(in) :: p
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: q
        integer :: s
        do s = 1, size(eps1)
            q = 0.2_dp*qf*s
            call check(error, eps1(s), q/(ei*(1.0_dp - p%rf*q/qf)), 'Newton: eps1 on loading', &
                       rel=2.0e-3_dp)
            if (allocated(error)) return
        end do
    end subroutine check_kondner

    !> Newton's corrections by GMRES with the last factorisation (docs/theory.md section 9,
    !> "Newton's corrections by GMRES"): the triaxial test of IIIB at 500 kPa to q = 0.8 qf
    !> in 4 steps of 40 increments (as test_newton), Newton to TOL 1e-11. Each increment converges to TOL
    !> (the largest accepted residual), eps1 follows Kondner's hyperbola (closed form, as
    !> test_kondner) to 0.2 %, and fewer numeric factorisations are made than the predictor,
    !> the midpoint corrector and one per Newton iteration would take (2 per increment plus
    !> the iterations): the corrections near convergence are GMRES's.
    subroutine test_newton_gmres(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: eps1(:), epsv(:)
        type(eb_params_t) :: p
        real(dp) :: qf, ei, worst
        integer :: increments, work(2)
        p = eb_parameters(table3_material(3), pa)
        qf = eb_failure_deviator(p, 500.0_dp)
        ei = eb_initial_modulus(p, 500.0_dp)
        call triaxial(table3_material(3), 500.0_dp, 0.2_dp*qf, 4, 40, solver_newton, eps1, &
                      epsv, error, residual=worst, increments=increments, work=work)
        if (allocated(error)) return
        write (*, '(a,3i6,es10.2)') '  increments, iterations, factorisations, residual', &
            increments, work, worst
        call check(error, worst <= 1.0e-11_dp, 'Newton: an increment above TOL')
        if (allocated(error)) return
        call check_kondner(eps1(1:4), p, qf, ei, error)
        if (allocated(error)) return
        call check(error, work(2) < 2*increments + work(1), 'no Newton correction by GMRES')
    end subroutine test_newton_gmres

    !> The sub-stepped E-B update (Newton's, docs/theory.md section 9 "Sub-steps") against
    !> the law's exact response: IIIB with Kb = 1 kPa, so that the lower Poisson bound holds
    !> everywhere (Bt = Et/3, nu_t = 0, D diagonal): a purely axial strain increment from the
    !> isotropic state at sigma3 = 500 kPa is then a drained triaxial test at constant
    !> sigma3 (d sigma_r = Et d eps_r = 0 exactly), whose deviator follows Kondner's
    !> hyperbola q = Ei eps1 / (1 + Rf Ei eps1 / qf) (Duncan & Chang 1970; section 8).
    !> eps1 is that of q = 0.9 qf, taken in one increment: with one step the midpoint rule
    !> is past its limit point and misses q by more than half; with the sub-steps of
    !> update_substeps (more than one) q within 2 %; the error falls as n^-2 (order >= 1.8
    !> from 16 to 32 sub-steps, the midpoint rule's) and is below 1e-3 of q at 64.
    subroutine test_substep_update(error)
        type(error_t), allocatable, intent(out) :: error
        type(material_t) :: mat
        type(eb_params_t) :: p
        real(dp) :: qf, q1, eps1, sig0(4), de(4), new(4), mid(4), d0(4, 4)
        real(dp) :: ei, history(2), err(3), order
        integer :: k, counts(3)
        mat = table3_material(3)
        mat%k_bulk = 1.0_dp
        p = eb_parameters(mat, pa)
        qf = eb_failure_deviator(p, 500.0_dp)
        q1 = 0.9_dp*qf
        ei = eb_initial_modulus(p, 500.0_dp)
        eps1 = q1/(ei*(1.0_dp - p%rf*q1/qf))
        ! tension positive, (r, z, theta, rz): the axial strain is compressive
        sig0 = [-500.0_dp, -500.0_dp, -500.0_dp, 0.0_dp]
        de = [0.0_dp, -eps1, 0.0_dp, 0.0_dp]
        history = 0.0_dp
        call eb_tangent(p, sig0, 0.0_dp, d0)
        call material_update(mat, pa, sig0, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], history, de, &
                             .true., new, mid)
        write (*, '(a,es10.3)') '  one step: q/q_ref - 1 =', (-new(2) - 500.0_dp)/q1 - 1.0_dp
        call check(error, abs((-new(2) - 500.0_dp)/q1 - 1.0_dp) > 0.5_dp, &
                   'one midpoint step should miss q by more than half (limit point)')
        if (allocated(error)) return
        counts = [update_substeps(mat, pa, sig0, history, de, d0), 16, 32]
        call check(error, counts(1) > 1 .and. counts(1) <= max_substeps, &
                   'update_substeps should ask for sub-steps here')
        if (allocated(error)) return
        do k = 1, 3
            call material_update(mat, pa, sig0, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], history, &
                                 de, .true., new, mid, substeps=counts(k))
            err(k) = abs((-new(2) - 500.0_dp)/q1 - 1.0_dp)
            write (*, '(a,i3,a,es10.3,a,es10.3)') '  sub-steps', counts(k), &
                ': |q/q_ref - 1| =', err(k), ', sigma_r + 500 =', new(1) + 500.0_dp
            call check(error, abs(new(1) + 500.0_dp) <= 1.0e-9_dp*q1, &
                       'sigma_r stays at the cell pressure')
            if (allocated(error)) return
        end do
        call check(error, err(1) <= 0.02_dp, 'q with update_substeps sub-steps within 2 %')
        if (allocated(error)) return
        order = log(err(2)/err(3))/log(2.0_dp)
        call check(error, order >= 1.8_dp, 'sub-stepped midpoint: error order from 16 to 32')
        if (allocated(error)) return
        call material_update(mat, pa, sig0, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], history, de, &
                             .true., new, mid, substeps=64)
        call check(error, -new(2) - 500.0_dp, q1, 'q with 64 sub-steps', rel=1.0e-3_dp)
    end subroutine test_substep_update

    !> Newton's tangent of the sub-stepped E-B update (the chain rule through the sub-steps,
    !> material_update_tangent with `substeps`) against central differences of the update
    !> with the same number of sub-steps: a fresh point loaded to near failure in one
    !> increment (plane strain), a stressed point loaded further, and a point that reloads
    !> through the unloading transition from below 0.75 SS_max (the case the transition
    !> part of the sub-step count is for); update_substeps asks for more than one sub-step
    !> in each. 1e-6 of the largest entry, as eb_consistent_tangent.
    subroutine test_substep_tangent(error)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: ncase = 3
        character(len=*), parameter :: names(ncase) = [character(len=24) :: &
            'fresh point', 'stressed point', 'reloading']
        real(dp), parameter :: s0(4, ncase) = reshape([ &
            -50.0_dp, -50.0_dp, -50.0_dp, 0.0_dp, &
            -300.0_dp, -700.0_dp, -300.0_dp, 50.0_dp, &
            -400.0_dp, -650.0_dp, -420.0_dp, 30.0_dp], [4, ncase])
        real(dp), parameter :: de0(4, ncase) = reshape([ &
            1.0e-3_dp, -4.0e-3_dp, 0.0_dp, 1.0e-3_dp, &
            -1.0e-3_dp, -2.0e-2_dp, 0.0_dp, 4.0e-3_dp, &
            2.0e-4_dp, -1.5e-3_dp, 0.0_dp, -2.0e-4_dp], [4, ncase])
        type(material_t) :: mat
        type(eb_params_t) :: p
        real(dp) :: history(2), c(4, 4), fd(4, 4), plus(4), minus(4), mid(4), de(4), h
        real(dp) :: d0(4, 4)
        integer :: k, j, nsub
        mat = table3_material(3)
        p = eb_parameters(mat, pa)
        do k = 1, ncase
            history = 0.0_dp
            ! reloading: the start below 0.75 of a past maximum that the increment passes
            if (k == 3) history(1) = eb_stress_state(p, s0(:, k))/0.6_dp
            call eb_tangent(p, s0(:, k), history(1), d0)
            nsub = update_substeps(mat, pa, s0(:, k), history, de0(:, k), d0)
            write (*, '(a,a,i3,a)') '  ', names(k), nsub, ' sub-steps'
            call check(error, nsub > 1, 'sub-step tangent, '//trim(names(k))// &
                       ': update_substeps asks for one step only')
            if (allocated(error)) return
            call material_update_tangent(mat, pa, s0(:, k), [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
                                         history, de0(:, k), c, substeps=nsub)
            h = 1.0e-5_dp*maxval(abs(de0(:, k)))
            do j = 1, 4
                de = de0(:, k)
                de(j) = de(j) + h
                call material_update(mat, pa, s0(:, k), [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
                                     history, de, .true., plus, mid, substeps=nsub)
                de(j) = de(j) - 2.0_dp*h
                call material_update(mat, pa, s0(:, k), [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
                                     history, de, .true., minus, mid, substeps=nsub)
                fd(:, j) = (plus - minus)/(2.0_dp*h)
            end do
            write (*, '(a,es10.3)') '    max |C - FD| / max |FD| =', &
                maxval(abs(c - fd))/maxval(abs(fd))
            call check(error, maxval(abs(c - fd)) <= 1.0e-6_dp*maxval(abs(fd)), &
                       'sub-step tangent, '//trim(names(k))//': analytic and central '// &
                       'differences differ')
            if (allocated(error)) return
        end do
    end subroutine test_substep_tangent

    !> Newton's line search takes the update and its tangent from one pass
    !> (material_update_with_tangent, whose states are the tangent's recursion's, D from
    !> eb_moduli_gradient): its stresses against material_update's (the update coded apart,
    !> D from eb_tangent) within 1e-12 of the largest stress, the same tangent as
    !> material_update_tangent within 1e-13 of its largest entry, and that tangent against
    !> central differences of material_update within 1e-6 (as eb_consistent_tangent); in one
    !> step and in update_substeps' sub-steps, loading and reloading (the points of
    !> substep_consistent_tangent), and unloading to Eur.
    subroutine test_update_with_tangent(error)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: ncase = 4
        character(len=24), parameter :: names(ncase) = [character(len=24) :: &
            'fresh point', 'stressed point', 'reloading', 'unloading']
        real(dp), parameter :: s0(4, ncase) = reshape([ &
            -50.0_dp, -50.0_dp, -50.0_dp, 0.0_dp, &
            -300.0_dp, -700.0_dp, -300.0_dp, 50.0_dp, &
            -400.0_dp, -650.0_dp, -420.0_dp, 30.0_dp, &
            -300.0_dp, -700.0_dp, -300.0_dp, 50.0_dp], [4, ncase])
        real(dp), parameter :: de0(4, ncase) = reshape([ &
            1.0e-3_dp, -4.0e-3_dp, 0.0_dp, 1.0e-3_dp, &
            -1.0e-3_dp, -2.0e-2_dp, 0.0_dp, 4.0e-3_dp, &
            2.0e-4_dp, -1.5e-3_dp, 0.0_dp, -2.0e-4_dp, &
            0.0_dp, 5.0e-4_dp, 0.0_dp, 0.0_dp], [4, ncase])
        real(dp), parameter :: zero4(4) = 0.0_dp
        type(material_t) :: mat
        type(eb_params_t) :: p
        real(dp) :: history(2), d0(4, 4), c(4, 4), c_apart(4, 4), fd(4, 4), de(4), h
        real(dp) :: s_new(4), s_mid(4), u_new(4), u_mid(4), plus(4), minus(4), mid(4)
        integer :: k, j, pass, nsub
        mat = table3_material(3)
        p = eb_parameters(mat, pa)
        do k = 1, ncase
            history = 0.0_dp
            if (k == 3) history(1) = eb_stress_state(p, s0(:, k))/0.6_dp
            if (k == 4) history(1) = eb_stress_state(p, s0(:, k))
            call eb_tangent(p, s0(:, k), history(1), d0)
            do pass = 1, 2
                nsub = 1
                if (pass == 2) nsub = max(2, update_substeps(mat, pa, s0(:, k), history, &
                                                             de0(:, k), d0))
                call material_update_with_tangent(mat, pa, s0(:, k), zero4, history, &
                                                  de0(:, k), d0, nsub, s_new, s_mid, c)
                call material_update(mat, pa, s0(:, k), zero4, history, de0(:, k), .true., &
                                     u_new, u_mid, d0, nsub)
                call material_update_tangent(mat, pa, s0(:, k), zero4, history, de0(:, k), &
                                             c_apart, d0, nsub)
                h = 1.0e-5_dp*maxval(abs(de0(:, k)))
                do j = 1, 4
                    de = de0(:, k)
                    de(j) = de(j) + h
                    call material_update(mat, pa, s0(:, k), zero4, history, de, .true., plus, &
                                         mid, d0, nsub)
                    de(j) = de(j) - 2.0_dp*h
                    call material_update(mat, pa, s0(:, k), zero4, history, de, .true., minus, &
                                         mid, d0, nsub)
                    fd(:, j) = (plus - minus)/(2.0_dp*h)
                end do
                write (*, '(a,a,i3,a,3es10.2)') '  ', names(k), nsub, &
                    ' sub-steps: stress, mid, tangent off by', &
                    maxval(abs(s_new - u_new))/maxval(abs(u_new)), &
                    maxval(abs(s_mid - u_mid))/maxval(abs(u_mid)), &
                    maxval(abs(c - fd))/maxval(abs(fd))
                call check(error, maxval(abs(s_new - u_new)) <= 1.0e-12_dp*maxval(abs(u_new)) &
                           .and. maxval(abs(s_mid - u_mid)) <= 1.0e-12_dp*maxval(abs(u_mid)), &
                           'one pass, '//trim(names(k))//': the update differs from '// &
                           'material_update')
                if (allocated(error)) return
                call check(error, maxval(abs(c - c_apart)) <= 1.0e-13_dp*maxval(abs(c_apart)), &
                           'one pass, '//trim(names(k))//': the tangent differs from '// &
                           'material_update_tangent')
                if (allocated(error)) return
                call check(error, maxval(abs(c - fd)) <= 1.0e-6_dp*maxval(abs(fd)), &
                           'one pass, '//trim(names(k))//': analytic and central '// &
                           'differences differ')
                if (allocated(error)) return
            end do
        end do
    end subroutine test_update_with_tangent
end module test_analysis_rockfill
