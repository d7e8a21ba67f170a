!> Unit tests of the pure E-B law against its formulas worked by hand (paper eqs. 19-21,
!> docs/theory.md section 8).
module test_materials_eb
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_elastic, only: elastic_dmatrix
    use cfrd_duncan_eb, only: eb_params_t, eb_state_t, eb_tangent, eb_friction_angle, &
                              eb_failure_deviator, eb_initial_modulus, eb_unload_modulus, &
                              eb_stress_state, eb_level_state
    implicit none
    private

    public :: collect_materials_eb

    real(dp), parameter :: pa = 101.325_dp

contains

    subroutine collect_materials_eb(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('friction_angle_eq20', test_phi), &
                new_unittest('tangent_is_isotropic_et_nut', test_tangent), &
                new_unittest('poisson_bounds', test_bounds), &
                new_unittest('floor_and_cap_keep_finite', test_floor_cap), &
                new_unittest('unloading_transition', test_transition), &
                new_unittest('level_state_closed_form', test_level_state) &
                ]
    end subroutine collect_materials_eb

    !> IIIB of Table 3.
    pure function iiib() result(p)
        type(eb_params_t) :: p
        p = eb_params_t(k=564.0_dp, n=0.35_dp, rf=0.85_dp, kb=204.0_dp, m=0.18_dp, &
                        phi0=51.0_dp, dphi=13.0_dp, kur=1128.0_dp, pa=pa, &
                        sigma3_floor=0.1_dp*pa)
    end function iiib

    !> phi = phi0 - dphi log10(s3/pa): phi0 at pa, phi0 - dphi at 10 pa.
    subroutine test_phi(error)
        type(error_t), allocatable, intent(out) :: error
        call check(error, eb_friction_angle(iiib(), pa), 51.0_dp, 'phi at pa', abs=1e-12_dp)
        if (allocated(error)) return
        call check(error, eb_friction_angle(iiib(), 10.0_dp*pa), 38.0_dp, 'phi at 10 pa', &
                   abs=1e-12_dp)
    end subroutine test_phi

    !> Plane stress state sxx = -300, syy = -700 (compression): sigma3 = 300, sigma1 = 700,
    !> q = 400; Et = K pa (s3/pa)^n (1 - Rf q/qf)^2, Bt = Kb pa (s3/pa)^m, and D is the
    !> isotropic matrix of Et and nu_t = (3Bt - Et)/(6Bt) (bounds checked inactive here).
    subroutine test_tangent(error)
        type(error_t), allocatable, intent(out) :: error
        type(eb_params_t) :: p
        type(eb_state_t) :: st
        real(dp) :: d(4, 4), et, bt, qf, nu
        p = iiib()
        call eb_tangent(p, [-300.0_dp, -700.0_dp, -300.0_dp, 0.0_dp], 0.0_dp, d, st)
        qf = eb_failure_deviator(p, 300.0_dp)
        et = 564.0_dp*pa*(300.0_dp/pa)**0.35_dp*(1.0_dp - 0.85_dp*400.0_dp/qf)**2
        bt = 204.0_dp*pa*(300.0_dp/pa)**0.18_dp
        call check(error, et/3.0_dp < bt .and. bt < et/0.06_dp, 'bounds inactive in this case')
        if (allocated(error)) return
        nu = (3.0_dp*bt - et)/(6.0_dp*bt)
        call check(error, st%et, et, 'Et', rel=1e-13_dp)
        if (allocated(error)) return
        call check(error, st%bt, bt, 'Bt', rel=1e-13_dp)
        if (allocated(error)) return
        call check(error, maxval(abs(d - elastic_dmatrix(et, nu))), 0.0_dp, 'D', &
                   abs=1e-12_dp*et)
    end subroutine test_tangent

    !> Bt below Et/3 is lifted to it (nu_t = 0); above Et/0.06 it is capped (nu_t = 0.49).
    subroutine test_bounds(error)
        type(error_t), allocatable, intent(out) :: error
        type(eb_params_t) :: p
        type(eb_state_t) :: st
        real(dp) :: d(4, 4)
        p = iiib()
        p%kb = 1.0_dp                       ! Bt far below Et/3
        call eb_tangent(p, [-500.0_dp, -500.0_dp, -500.0_dp, 0.0_dp], 0.0_dp, d, st)
        call check(error, st%nu_t, 0.0_dp, 'nu_t at the lower bound', abs=1e-14_dp)
        if (allocated(error)) return
        p%kb = 1.0e6_dp                     ! Bt far above Et/0.06
        call eb_tangent(p, [-500.0_dp, -500.0_dp, -500.0_dp, 0.0_dp], 0.0_dp, d, st)
        call check(error, st%nu_t, 0.49_dp, 'nu_t at the upper bound', abs=1e-14_dp)
    end subroutine test_bounds

    !> Tension and a deviator far beyond failure: moduli at the floor sigma3 = 0.1 pa and
    !> the cap S = 0.99, finite: Et = K pa (0.1)^n (1 - 0.85*0.99)^2.
    subroutine test_floor_cap(error)
        type(error_t), allocatable, intent(out) :: error
        type(eb_params_t) :: p
        type(eb_state_t) :: st
        real(dp) :: d(4, 4)
        p = iiib()
        call eb_tangent(p, [50.0_dp, -5000.0_dp, 0.0_dp, 10.0_dp], 0.0_dp, d, st)
        call check(error, st%level, 0.99_dp, 'stress level capped', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, st%et, 564.0_dp*pa*0.1_dp**0.35_dp*(1.0_dp - 0.85_dp*0.99_dp)**2, &
                   'Et at the floor and the cap', rel=1e-13_dp)
        if (allocated(error)) return
        call check(error, all(abs(d) < huge(1.0_dp)) .and. d(1, 1) > 0.0_dp, 'finite D')
    end subroutine test_floor_cap

    !> At SS = SS_max: Et; at SS = 0.75 SS_max or below: Eur; half-way (0.875): the mean.
    subroutine test_transition(error)
        type(error_t), allocatable, intent(out) :: error
        type(eb_params_t) :: p
        type(eb_state_t) :: st
        real(dp) :: d(4, 4), stress(4), ss, eur, et
        p = iiib()
        stress = [-500.0_dp, -1200.0_dp, -500.0_dp, 0.0_dp]
        ss = eb_stress_state(p, stress)
        eur = eb_unload_modulus(p, 500.0_dp)
        call eb_tangent(p, stress, ss, d, st)
        et = st%et
        call check(error, .not. st%unloading, 'at the past maximum: loading')
        if (allocated(error)) return
        call eb_tangent(p, stress, ss/0.75_dp, d, st)
        call check(error, st%et, eur, 'at 0.75 of the past maximum: Eur', rel=1e-13_dp)
        if (allocated(error)) return
        call eb_tangent(p, stress, ss/0.5_dp, d, st)
        call check(error, st%et, eur, 'below: Eur', rel=1e-13_dp)
        if (allocated(error)) return
        call eb_tangent(p, stress, ss/0.875_dp, d, st)
        call check(error, st%et, 0.5_dp*(et + eur), 'half-way: the mean', rel=1e-12_dp)
    end subroutine test_transition

    !> eb_level_state against the closed form worked by hand: sxx = -300, syy = -700,
    !> sxy = -150 kPa (tension positive) have the in-plane principal stresses
    !> 500 -+ hypot(200, 150) = 250 and 750 kPa (compression positive), so with IIIB
    !> (c = 0) phi = 51 - 13 log10(250/pa) degrees (eq. 20), (s1 - s3)_f =
    !> 2 s3 sin phi / (1 - sin phi) (eq. 19), S = 500 / (s1 - s3)_f and
    !> SS = S (250/pa)^(1/4). The same S gives eb_tangent's Et = Ei (1 - Rf S)^2 with
    !> Ei = K pa (250/pa)^n and its Bt = Kb pa (250/pa)^m (loading, ss_max = 0); SS is
    !> eb_stress_state's.
    subroutine test_level_state(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: deg = acos(-1.0_dp)/180.0_dp
        real(dp), parameter :: stress(4) = [-300.0_dp, -700.0_dp, -300.0_dp, -150.0_dp]
        type(eb_params_t) :: p
        type(eb_state_t) :: st
        real(dp) :: d(4, 4), level, ss, phi, qf, s_hand, ss_hand, et_hand, bt_hand
        p = iiib()
        call eb_level_state(p, stress, level, ss)
        phi = (51.0_dp - 13.0_dp*log10(250.0_dp/pa))*deg
        qf = 2.0_dp*250.0_dp*sin(phi)/(1.0_dp - sin(phi))
        s_hand = 500.0_dp/qf
        ss_hand = s_hand*(250.0_dp/pa)**0.25_dp
        call check(error, s_hand > 0.1_dp .and. s_hand < 0.9_dp, 'level below the cap')
        if (allocated(error)) return
        call check(error, level, s_hand, 'S against the closed form', rel=1e-13_dp)
        if (allocated(error)) return
        call check(error, ss, ss_hand, 'SS against the closed form', rel=1e-13_dp)
        if (allocated(error)) return
        call check(error, ss, eb_stress_state(p, stress), 'SS as eb_stress_state', &
                   rel=1e-15_dp)
        if (allocated(error)) return
        call eb_tangent(p, stress, 0.0_dp, d, st)
        call check(error, st%level, level, 'S as eb_tangent', rel=1e-15_dp)
        if (allocated(error)) return
        et_hand = 564.0_dp*pa*(250.0_dp/pa)**0.35_dp*(1.0_dp - 0.85_dp*s_hand)**2
        bt_hand = 204.0_dp*pa*(250.0_dp/pa)**0.18_dp
        call check(error, st%et, et_hand, 'Et = Ei (1 - Rf S)^2', rel=1e-12_dp)
        if (allocated(error)) return
        call check(error, st%bt, bt_hand, 'Bt = Kb pa (s3/pa)^m', rel=1e-13_dp)
    end subroutine test_level_state
end module test_materials_eb
