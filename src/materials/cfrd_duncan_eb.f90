!> The Duncan-Chang E-B law for rockfill (Duncan et al. 1980; paper eqs. 18-21) as pure
!> functions of the stress, the Gauss-point history and the parameters
!> (docs/theory.md, section 8). Inside the law compression is positive; the finite-element
!> code keeps tension positive and the conversion happens here, at the law's boundary.
module cfrd_duncan_eb
    use cfrd_kinds, only: dp
    use cfrd_elastic, only: elastic_dmatrix
    implicit none
    private

    public :: eb_params_t, eb_state_t, eb_tangent, eb_stress_state, eb_initial_modulus
    public :: eb_failure_deviator, eb_friction_angle, eb_principal, eb_unload_modulus
    public :: nu_t_max, eb_linear_moduli, eb_initial_moduli, eb_moduli_gradient, eb_substeps
    public :: eb_level_state

    !> Upper bound of the tangent Poisson ratio: Bt <= Et / (3 (1 - 2 nu_t_max)).
    real(dp), parameter :: nu_t_max = 0.49_dp
    real(dp), parameter :: deg = 0.017453292519943295769_dp
    real(dp), parameter :: ln10 = 2.302585092994045684_dp
    !> Width of the loading-to-unloading transition, as a fraction of the past maximum of
    !> the stress-state function.
    real(dp), parameter :: transition = 0.25_dp
    !> Below this past maximum of SS a point counts as loading: near-isotropic states, whose
    !> stress level is round-off, would otherwise flip between the branches at random.
    real(dp), parameter :: ss_threshold = 0.01_dp

    !> Parameters of one E-B material (kPa, degrees, dimensionless).
    type :: eb_params_t
        real(dp) :: k = 0.0_dp, n = 0.0_dp, rf = 0.0_dp, kb = 0.0_dp, m = 0.0_dp
        real(dp) :: phi0 = 0.0_dp, dphi = 0.0_dp, cohesion = 0.0_dp
        real(dp) :: kur = 0.0_dp
        real(dp) :: pa = 101.325_dp
        real(dp) :: sigma3_floor = 10.1325_dp    !! kPa, floor on sigma3 in the moduli
        real(dp) :: level_cap = 0.99_dp          !! cap of the stress level
    end type eb_params_t

    !> What the law saw at a point, for output and tests.
    type :: eb_state_t
        real(dp) :: sigma1 = 0.0_dp, sigma3 = 0.0_dp   !! in-plane principal, compression +
        real(dp) :: phi = 0.0_dp                       !! degrees
        real(dp) :: level = 0.0_dp                     !! stress level S, capped
        real(dp) :: et = 0.0_dp, bt = 0.0_dp, nu_t = 0.0_dp
        logical :: unloading = .false.
    end type eb_state_t

contains

    !> In-plane principal stresses, compression positive: sigma1 >= sigma3, from the FE
    !> stress (xx, yy, zz, xy) with tension positive.
    pure subroutine eb_principal(stress, sigma1, sigma3)
        real(dp), intent(in) :: stress(4)
        real(dp), intent(out) :: sigma1, sigma3
        real(dp) :: centre, radius
        centre = -0.5_dp*(stress(1) + stress(2))
        radius = circle_radius(0.5_dp*(stress(1) - stress(2)), stress(4))
        sigma1 = centre + radius
        sigma3 = centre - radius
    end subroutine eb_principal

    !> Friction angle (degrees) at confining stress sigma3 (eq. 20), sigma3 floored.
    pure real(dp) function eb_friction_angle(p, sigma3) result(phi)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: sigma3
        phi = friction_angle(p, log_ratio(p, sigma3))
    end function eb_friction_angle

    !> ln(sigma3/pa) of sigma3 floored: the one logarithm an evaluation of the law takes.
    !> log10(sigma3/pa) = ln(sigma3/pa)/ln 10 and (sigma3/pa)^x = exp(x ln(sigma3/pa))
    !> follow from it (one log and an exp for each power, in place of a log10 and a pow for
    !> each: the same values to a few units in the last place).
    pure real(dp) function log_ratio(p, sigma3) result(t)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: sigma3
        t = log(max(sigma3, p%sigma3_floor)/p%pa)
    end function log_ratio

    !> (sigma3/pa)^(1/4) of sigma3 floored: the factor of Duncan's stress-state function
    !> SS = S (sigma3/pa)^(1/4).
    pure real(dp) function quarter_root(p, sigma3) result(r)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: sigma3
        r = sqrt(sqrt(max(sigma3, p%sigma3_floor)/p%pa))
    end function quarter_root

    !> The friction angle (degrees, clamped to [1, 89]) from t = ln(sigma3/pa) (eq. 20).
    pure real(dp) function friction_angle(p, t) result(phi)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: t
        phi = p%phi0 - p%dphi*(t/ln10)
        phi = min(max(phi, 1.0_dp), 89.0_dp)
    end function friction_angle

    !> The deviator at failure (eb_failure_deviator) of floored s3, t = ln(s3/pa).
    pure real(dp) function failure_deviator(p, s3, t) result(qf)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: s3, t
        real(dp) :: phi, sphi
        phi = friction_angle(p, t)*deg
        sphi = sin(phi)
        qf = (2.0_dp*p%cohesion*cos(phi) + 2.0_dp*s3*sphi)/(1.0_dp - sphi)
    end function failure_deviator

    !> sqrt(a^2 + b^2), the radius of Mohr's circle: stresses in kPa are far from
    !> overflow and underflow, so the plain form serves (hypot guards against both, at
    !> several times the cost).
    pure real(dp) function circle_radius(a, b) result(r)
        real(dp), intent(in) :: a, b
        r = sqrt(a*a + b*b)
    end function circle_radius

    !> Deviator at failure (Mohr-Coulomb, as in eq. 19):
    !> (sigma1 - sigma3)_f = (2 c cos phi + 2 sigma3 sin phi) / (1 - sin phi).
    pure real(dp) function eb_failure_deviator(p, sigma3) result(qf)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: sigma3
        qf = failure_deviator(p, max(sigma3, p%sigma3_floor), log_ratio(p, sigma3))
    end function eb_failure_deviator

    !> Initial tangent modulus Ei = K pa (sigma3/pa)^n.
    pure real(dp) function eb_initial_modulus(p, sigma3) result(ei)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: sigma3
        ei = p%k*p%pa*exp(p%n*log_ratio(p, sigma3))
    end function eb_initial_modulus

    !> The moduli of the linear-elastic stand-in for the law (EFFECTS card, ROCKFILL LINEAR):
    !> the initial moduli at sigma3 = pa (docs/theory.md section 8).
    pure subroutine eb_linear_moduli(p, e, nu)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(out) :: e, nu
        call eb_initial_moduli(p, p%pa, e, nu)
    end subroutine eb_linear_moduli

    !> The law's moduli at stress level 0 and confining stress sigma3 (kPa, compression +,
    !> floored): Ei = K pa (sigma3/pa)^n, B = Kb pa (sigma3/pa)^m bounded as in eb_tangent,
    !> and nu = (3 B - Ei) / (6 B).
    pure subroutine eb_initial_moduli(p, sigma3, e, nu)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: sigma3
        real(dp), intent(out) :: e, nu
        real(dp) :: b
        e = eb_initial_modulus(p, sigma3)
        b = p%kb*p%pa*exp(p%m*log_ratio(p, sigma3))
        b = min(max(b, e/3.0_dp), e/(3.0_dp*(1.0_dp - 2.0_dp*nu_t_max)))
        nu = (3.0_dp*b - e)/(6.0_dp*b)
    end subroutine eb_initial_moduli

    !> Unload-reload modulus Eur = Kur pa (sigma3/pa)^n.
    pure real(dp) function eb_unload_modulus(p, sigma3) result(eur)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: sigma3
        eur = p%kur*p%pa*exp(p%n*log_ratio(p, sigma3))
    end function eb_unload_modulus

    !> Duncan's stress-state function SS = S (sigma3/pa)^(1/4), whose past maximum decides
    !> between loading and unloading (Duncan et al. 1980).
    pure real(dp) function eb_stress_state(p, stress) result(ss)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: stress(4)
        real(dp) :: level
        call eb_level_state(p, stress, level, ss)
    end function eb_stress_state

    !> The stress level S (capped, as eb_tangent takes it) and the stress-state function
    !> SS = S (sigma3/pa)^(1/4) of one stress (tension positive), from one evaluation of
    !> the principal stresses and the strength: what a point's history needs
    !> (cfrd_material_law: update_history), without the tangent matrix. `minor`: sigma3
    !> (compression positive, not floored), as eb_tangent's state has it.
    pure subroutine eb_level_state(p, stress, level, ss, minor)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: stress(4)
        real(dp), intent(out) :: level, ss
        real(dp), intent(out), optional :: minor
        real(dp) :: sigma1, sigma3
        call eb_principal(stress, sigma1, sigma3)
        level = stress_level(p, sigma1, sigma3)
        ss = level*quarter_root(p, sigma3)
        if (present(minor)) minor = sigma3
    end subroutine eb_level_state

    !> How many sub-steps the midpoint update from `stress` to about `trial` (its forward
    !> Euler prediction, tension positive) needs so that no sub-step takes its half-way
    !> state more than `reach` of the way to the limit point of the one-step rule
    !> (docs/theory.md section 9, "Sub-steps"), as a real number (the caller rounds up):
    !> - loading, the modulus falls as (1 - Rf S)^2: the limit point of one step is at
    !>   the half-way rise (1 - Rf S_0)/(3 Rf) of S, so n = Rf dS / (2 reach (1 - Rf S_0))
    !>   with dS the rise of the uncapped stress level from S_0 (capped) to the trial;
    !> - reloading through the unloading transition (SS_max above the loading threshold,
    !>   the trial's SS above (1 - transition) SS_max, the start's below SS_max): there the
    !>   modulus falls from Eur to Et over a rise of transition SS_max, and one step of
    !>   half-way rise dSS/2 loses its stiffness when (Eur - Et) dSS/2 exceeds
    !>   Et transition SS_max (Et at the top of the transition, Eur at the start's sigma3):
    !>   n = (Eur - Et) dSS / (2 transition SS_max Et) / (3 reach).
    pure real(dp) function eb_substeps(p, stress, ss_max, trial, reach) result(n)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: stress(4), ss_max, trial(4), reach
        real(dp) :: sigma1, sigma3, t, s0, trial1, trial3, trial_level, rise, ss0, ss1, root4
        real(dp) :: et_top, eur
        ! each stress's principal values and strength once (one logarithm each)
        call eb_principal(stress, sigma1, sigma3)
        t = log_ratio(p, sigma3)
        s0 = (sigma1 - sigma3)/failure_deviator(p, max(sigma3, p%sigma3_floor), t)
        s0 = min(max(s0, 0.0_dp), p%level_cap)
        call eb_principal(trial, trial1, trial3)
        trial_level = (trial1 - trial3)/eb_failure_deviator(p, trial3)
        rise = max(trial_level, 0.0_dp) - s0
        n = max(p%rf*rise/(2.0_dp*reach*(1.0_dp - p%rf*s0)), 0.0_dp)
        if (ss_max <= ss_threshold) return
        root4 = quarter_root(p, sigma3)
        ss0 = s0*root4
        ss1 = min(max(trial_level, 0.0_dp), p%level_cap)*quarter_root(p, trial3)
        if (ss0 >= ss_max .or. ss1 <= (1.0_dp - transition)*ss_max) return
        et_top = p%k*p%pa*exp(p%n*t)*(1.0_dp - p%rf*min(ss_max/root4, p%level_cap))**2
        eur = p%kur*p%pa*exp(p%n*t)
        if (eur <= et_top) return
        n = max(n, (eur - et_top)*(ss1 - ss0)/(2.0_dp*transition*ss_max*et_top)/ &
                   (3.0_dp*reach))
    end function eb_substeps

    pure real(dp) function stress_level(p, sigma1, sigma3) result(level)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: sigma1, sigma3
        level = (sigma1 - sigma3)/eb_failure_deviator(p, sigma3)
        level = min(max(level, 0.0_dp), p%level_cap)
    end function stress_level

    !> Tangent matrix d(4,4) (FE component order, cfrd_elastic) at `stress` (tension
    !> positive) with `ss_max`, the past maximum of the stress-state function at this point:
    !> Et of eq. 19 when loading, Eur when SS < ss_max, Bt of eq. 21 bounded so that the
    !> tangent Poisson ratio stays in [0, 0.49]. Finite and positive definite for any stress.
    !> (`unloading` in `state` is true once SS is below its past maximum.)
    pure subroutine eb_tangent(p, stress, ss_max, d, state)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: stress(4), ss_max
        real(dp), intent(out) :: d(4, 4)
        type(eb_state_t), intent(out), optional :: state
        real(dp) :: sigma1, sigma3, s3, t, power_n, level, et, bt, nu_t, ss, weight
        logical :: unloading
        call eb_principal(stress, sigma1, sigma3)
        s3 = max(sigma3, p%sigma3_floor)
        t = log_ratio(p, sigma3)
        level = (sigma1 - sigma3)/failure_deviator(p, s3, t)
        level = min(max(level, 0.0_dp), p%level_cap)
        ss = level*quarter_root(p, s3)
        power_n = exp(p%n*t)
        ! Loading (SS at its past maximum): Et of eq. 19. Unloading: the modulus moves
        ! linearly from Et to Eur as SS falls from its past maximum to 0.75 of it, and is Eur
        ! below (the transition of Duncan et al. 1980). A sharp switch makes the incremental
        ! solution chatter between the branches (docs/theory.md section 8).
        et = p%k*p%pa*power_n*(1.0_dp - p%rf*level)**2
        unloading = .false.
        if (ss_max > ss_threshold .and. ss < ss_max) then
            weight = min(1.0_dp, (ss_max - ss)/(transition*ss_max))
            et = et + weight*max(p%kur*p%pa*power_n - et, 0.0_dp)
            unloading = weight > 0.0_dp
        end if
        bt = p%kb*p%pa*exp(p%m*t)
        bt = min(max(bt, et/3.0_dp), et/(3.0_dp*(1.0_dp - 2.0_dp*nu_t_max)))
        nu_t = (3.0_dp*bt - et)/(6.0_dp*bt)
        d = elastic_dmatrix(et, nu_t)
        if (present(state)) then
            state = eb_state_t(sigma1=sigma1, sigma3=sigma3, phi=friction_angle(p, t), &
                               level=level, et=et, bt=bt, nu_t=nu_t, unloading=unloading)
        end if
    end subroutine eb_tangent

    !> Et and Bt as eb_tangent takes them at `stress` (tension positive) with `ss_max`, and
    !> their gradients with respect to the four stress components (docs/theory.md section
    !> 8, "Derivatives of the moduli"): every branch differentiated as eb_tangent takes it.
    !> Where a cap, floor or clamp acts, the capped quantity does not depend on the stress;
    !> at an isotropic in-plane state the principal directions are undefined and the radius
    !> is taken as constant (its gradient, a unit vector in any direction, is set to zero).
    pure subroutine eb_moduli_gradient(p, stress, ss_max, et, bt, det, dbt)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: stress(4), ss_max
        real(dp), intent(out) :: et, bt, det(4), dbt(4)
        real(dp) :: t, power_n
        real(dp) :: half_difference, radius, dradius(4), sigma3, s3, ds3(4)
        real(dp) :: phi, dphi_ds3, sphi, cphi, qf, dqf_ds3, level_raw, level, dlevel(4)
        real(dp) :: ei, dei(4), eload, deload(4), root4, ss, dss(4), weight_raw, dweight(4)
        real(dp) :: eur, deur(4), b_raw, db_raw(4), b_low, b_high
        ! principal stresses, compression positive (eb_principal)
        half_difference = 0.5_dp*(stress(1) - stress(2))
        radius = circle_radius(half_difference, stress(4))
        dradius = 0.0_dp
        if (radius > 0.0_dp) dradius = [0.5_dp*half_difference/radius, &
                                        -0.5_dp*half_difference/radius, 0.0_dp, &
                                        stress(4)/radius]
        sigma3 = -0.5_dp*(stress(1) + stress(2)) - radius
        s3 = max(sigma3, p%sigma3_floor)
        ds3 = 0.0_dp
        if (sigma3 > p%sigma3_floor) ds3 = [-0.5_dp, -0.5_dp, 0.0_dp, 0.0_dp] - dradius
        ! strength (eqs. 19-20): phi in degrees, clamped to [1, 89]
        t = log(s3/p%pa)
        power_n = exp(p%n*t)
        phi = p%phi0 - p%dphi*(t/ln10)
        dphi_ds3 = -p%dphi/(s3*ln10)
        if (phi <= 1.0_dp .or. phi >= 89.0_dp) dphi_ds3 = 0.0_dp
        phi = min(max(phi, 1.0_dp), 89.0_dp)*deg
        dphi_ds3 = dphi_ds3*deg
        sphi = sin(phi)
        cphi = cos(phi)
        qf = (2.0_dp*p%cohesion*cphi + 2.0_dp*s3*sphi)/(1.0_dp - sphi)
        dqf_ds3 = 2.0_dp*sphi/(1.0_dp - sphi) + dphi_ds3* &
                  (-2.0_dp*p%cohesion*sphi + 2.0_dp*s3*cphi + qf*cphi)/(1.0_dp - sphi)
        ! stress level S = (sigma1 - sigma3) / qf, in [0, cap]
        level_raw = 2.0_dp*radius/qf
        level = min(max(level_raw, 0.0_dp), p%level_cap)
        dlevel = 0.0_dp
        if (level_raw > 0.0_dp .and. level_raw < p%level_cap) &
            dlevel = (2.0_dp*dradius - level_raw*dqf_ds3*ds3)/qf
        ! loading modulus (eq. 19)
        ei = p%k*p%pa*power_n
        dei = p%n*ei/s3*ds3
        eload = ei*(1.0_dp - p%rf*level)**2
        deload = dei*(1.0_dp - p%rf*level)**2 - 2.0_dp*p%rf*ei*(1.0_dp - p%rf*level)*dlevel
        et = eload
        det = deload
        ! unloading: Et moves to Eur as SS falls from ss_max to (1 - transition) ss_max
        root4 = quarter_root(p, s3)
        ss = level*root4
        if (ss_max > ss_threshold .and. ss < ss_max) then
            dss = dlevel*root4 + 0.25_dp*level*root4/s3*ds3
            weight_raw = (ss_max - ss)/(transition*ss_max)
            dweight = 0.0_dp
            if (weight_raw < 1.0_dp) dweight = -dss/(transition*ss_max)
            eur = p%kur*p%pa*power_n
            deur = p%n*eur/s3*ds3
            if (eur > eload) then
                et = eload + min(1.0_dp, weight_raw)*(eur - eload)
                det = deload + dweight*(eur - eload) + min(1.0_dp, weight_raw)*(deur - deload)
            end if
        end if
        ! bulk modulus (eq. 21) within the Poisson bounds
        b_raw = p%kb*p%pa*exp(p%m*t)
        db_raw = p%m*b_raw/s3*ds3
        b_low = et/3.0_dp
        b_high = et/(3.0_dp*(1.0_dp - 2.0_dp*nu_t_max))
        if (b_raw <= b_low) then
            bt = b_low
            dbt = det/3.0_dp
        else if (b_raw >= b_high) then
            bt = b_high
            dbt = det/(3.0_dp*(1.0_dp - 2.0_dp*nu_t_max))
        else
            bt = b_raw
            dbt = db_raw
        end if
    end subroutine eb_moduli_gradient
end module cfrd_duncan_eb
