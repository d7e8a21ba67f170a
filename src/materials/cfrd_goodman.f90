!> The Goodman interface law of a zero-thickness joint (Goodman, Taylor & Brekke 1968;
!> paper eqs. 5-7; docs/theory.md section 12) as pure functions. Tractions (sigma_n, tau)
!> and relative displacements (du_n, du_s) of the joint's frame, tension and opening
!> positive; inside eq. (7) the compressive normal stress p = -sigma_n is used.
!>
!> - Normal: sigma_n = kn_c du_n while the joint is closed (du_n <= 0), kn_t du_n when it is
!>   open; with the tension cut-off an open joint carries sigma_n = 0 (and tau = 0). The
!>   normal response depends on the total du_n only, so a joint that opens and closes
!>   again comes back to the same stress.
!> - Shear: d tau = ks d du_s with ks of eq. (7),
!>   ks = k1 gamma_w (p/pa)^n1 (1 - Rf1 |tau| / (p tan phi))^2, p floored at sigma_n_floor,
!>   integrated exactly over an increment at the increment's mid normal stress: with
!>   g = 1 - Rf1 |tau| / tau_f the law is dg/ds = -ks_i Rf1/tau_f g^2, so
!>   g1 = g0 / (1 + ks_i Rf1/tau_f |d du_s| g0) (the Clough-Duncan hyperbola, whatever the
!>   increment's size). A slip against the shear stress unloads with the initial ks_i
!>   until tau passes zero. The shear stress is then capped at the Coulomb limit
!>   |tau| <= max(p, 0) tan phi: with Rf1 = 1 the hyperbola approaches it, with Rf1 < 1 it
!>   reaches it at a finite slip and stays there.
!> - Tangent floors (only for a regular stiffness matrix; the stresses do not use them):
!>   the hyperbolic factor at ks_residual, and an open joint's ks at kn_t.
!> The tangent handed to Newton's iterations (goodman_update_tangent) is the derivative of
!> this update with respect to the increment: kn at the end, the hyperbola's ks_i g^2 with
!> its dependence on the mid normal stress, and at the Coulomb cap d tau / d du_n =
!> -sign(tau) tan(phi) kn (docs/theory.md section 12.3); floors aside, it is exact, so
!> Newton converges quadratically wherever the law is smooth.
module cfrd_goodman
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: goodman_params_t, goodman_tangent, goodman_update, goodman_shear_stiffness
    public :: goodman_update_tangent
    public :: goodman_normal_stress, coulomb_limit

    real(dp), parameter :: deg = 0.017453292519943295769_dp
    !> Floor of the hyperbolic factor (1 - Rf1 tau / tau_f)^2 in the tangent.
    real(dp), parameter :: ks_residual = 1.0e-4_dp

    type :: goodman_params_t
        real(dp) :: kn_compression = 0.0_dp   !! kPa/m
        real(dp) :: kn_tension = 0.0_dp       !! kPa/m
        real(dp) :: k1 = 0.0_dp, n1 = 0.0_dp, rf1 = 0.0_dp
        real(dp) :: phi = 0.0_dp              !! deg
        real(dp) :: gamma_w = 9.81_dp         !! kN/m3
        real(dp) :: pa = 101.325_dp           !! kPa
        real(dp) :: sigma_n_floor = 10.1325_dp   !! kPa
        logical :: tension_cutoff = .false.
    end type goodman_params_t

contains

    !> Normal traction for the total normal relative displacement un.
    pure real(dp) function goodman_normal_stress(p, un) result(sn)
        type(goodman_params_t), intent(in) :: p
        real(dp), intent(in) :: un
        sn = normal_stiffness(p, un)*un
    end function goodman_normal_stress

    !> d sigma_n / d du_n at un: kn_c closed, kn_t open, 0 open with the tension cut-off.
    pure real(dp) function normal_stiffness(p, un) result(kn)
        type(goodman_params_t), intent(in) :: p
        real(dp), intent(in) :: un
        if (un <= 0.0_dp) then
            kn = p%kn_compression
        else if (p%tension_cutoff) then
            kn = 0.0_dp
        else
            kn = p%kn_tension
        end if
    end function normal_stiffness

    !> Coulomb limit tau_f = max(-sigma_n, 0) tan phi.
    pure real(dp) function coulomb_limit(p, sn) result(tf)
        type(goodman_params_t), intent(in) :: p
        real(dp), intent(in) :: sn
        tf = max(-sn, 0.0_dp)*tan(p%phi*deg)
    end function coulomb_limit

    !> Shear stiffness ks of eq. (7) at (sigma_n, tau), with the tangent floors.
    pure real(dp) function goodman_shear_stiffness(p, sn, tau, un) result(ks)
        type(goodman_params_t), intent(in) :: p
        real(dp), intent(in) :: sn, tau, un
        real(dp) :: pn, factor
        if (un > 0.0_dp) then
            ks = p%kn_tension
            return
        end if
        pn = max(-sn, p%sigma_n_floor)
        factor = max(1.0_dp - p%rf1*abs(tau)/(pn*tan(p%phi*deg)), 0.0_dp)**2
        ks = p%k1*p%gamma_w*(pn/p%pa)**p%n1*max(factor, ks_residual)
    end function goodman_shear_stiffness

    !> Tangent d(2,2) = diag(kn, ks) (eq. 6) at tractions s = (sigma_n, tau) and total
    !> normal relative displacement un.
    pure subroutine goodman_tangent(p, s, un, d)
        type(goodman_params_t), intent(in) :: p
        real(dp), intent(in) :: s(2), un
        real(dp), intent(out) :: d(2, 2)
        d = 0.0_dp
        d(1, 1) = merge(p%kn_tension, p%kn_compression, un > 0.0_dp)
        d(2, 2) = goodman_shear_stiffness(p, s(1), s(2), un)
    end subroutine goodman_tangent

    !> Shear stress after the slip ds from tau0 at compressive normal stress pn (eq. 7
    !> integrated exactly at constant pn; a slip against tau0 unloads with ks_i first).
    pure real(dp) function hyperbolic_shear(p, tau0, ds, pn) result(tau)
        type(goodman_params_t), intent(in) :: p
        real(dp), intent(in) :: tau0, ds, pn
        real(dp) :: dtau_ds, dtau_dpn
        call hyperbolic_shear_derivatives(p, tau0, ds, pn, tau, dtau_ds, dtau_dpn)
    end function hyperbolic_shear

    !> Tractions after the relative displacement increment de = (d du_n, d du_s) from s at
    !> total normal relative displacement un: normal exact, shear along the hyperbola at the
    !> increment's mid normal stress, then the Coulomb cap. s_mid: the tractions half-way.
    !> (`midpoint` is part of the laws' common interface; both integrations here are exact.)
    pure subroutine goodman_update(p, s, un, de, midpoint, s_new, s_mid)
        type(goodman_params_t), intent(in) :: p
        real(dp), intent(in) :: s(2), un, de(2)
        logical, intent(in) :: midpoint
        real(dp), intent(out) :: s_new(2), s_mid(2)
        s_mid(1) = goodman_normal_stress(p, un + 0.5_dp*de(1))
        s_new(1) = goodman_normal_stress(p, un + de(1))
        s_mid(2) = capped(hyperbolic_shear(p, s(2), 0.5_dp*de(2), -s_mid(1)), s_mid(1))
        s_new(2) = capped(hyperbolic_shear(p, s(2), de(2), -s_mid(1)), s_new(1))
        if (midpoint) continue
    contains
        pure real(dp) function capped(tau, sn)
            real(dp), intent(in) :: tau, sn
            capped = sign(min(abs(tau), coulomb_limit(p, sn)), tau)
        end function capped
    end subroutine goodman_update
    !> Shear after the slip ds from tau0 at compressive normal stress pn (eq. 7 integrated
    !> exactly at constant pn, a slip against tau0 unloading with ks_i first) and its
    !> derivatives d tau / d ds and d tau / d pn. At ds = 0 the derivative is the
    !> one of continued loading in the direction of tau0 (the first Newton iteration).
    pure recursive subroutine hyperbolic_shear_derivatives(p, tau0, ds, pn, tau, dtau_ds, &
                                                           dtau_dpn)
        type(goodman_params_t), intent(in) :: p
        real(dp), intent(in) :: tau0, ds, pn
        real(dp), intent(out) :: tau, dtau_ds, dtau_dpn
        real(dp) :: pf, dpf, ks_i, dks_i, b, g0, g, q, t0, a, dg, r, h_r, h_pn
        pf = max(pn, p%sigma_n_floor)
        dpf = merge(1.0_dp, 0.0_dp, pn > p%sigma_n_floor)   ! d pf / d pn
        ks_i = p%k1*p%gamma_w*(pf/p%pa)**p%n1
        dks_i = p%n1*ks_i/pf*dpf                            ! d ks_i / d pn
        b = p%rf1/(pf*tan(p%phi*deg))
        tau = tau0
        dtau_dpn = 0.0_dp
        t0 = abs(tau0)
        if (tau0*ds < 0.0_dp) then
            tau = tau0 + ks_i*ds
            dtau_ds = ks_i
            dtau_dpn = dks_i*ds
            if (tau*tau0 >= 0.0_dp) return
            ! Past zero: loading from zero over the remaining slip r = tau0/ks_i + ds.
            r = tau/ks_i
            call hyperbolic_shear_derivatives(p, 0.0_dp, r, pn, tau, h_r, h_pn)
            dtau_ds = h_r
            dtau_dpn = h_pn - h_r*tau0*dks_i/ks_i**2
            return
        end if
        a = abs(ds)
        if (b == 0.0_dp) then
            tau = sign(t0 + ks_i*a, merge(tau0, ds, ds == 0.0_dp))
            dtau_ds = ks_i
            dtau_dpn = sign(a*dks_i, ds)
            return
        end if
        g0 = 1.0_dp - b*t0
        if (g0 <= 0.0_dp) then
            dtau_ds = 0.0_dp
            return
        end if
        q = ks_i*b*a
        g = g0/(1.0_dp + q*g0)
        dtau_ds = ks_i*g**2
        if (ds == 0.0_dp) return
        ! d/d pn of t = (1 - g)/b, with b ~ 1/pf, g0 = 1 - b t0, q ~ pf^(n1 - 1).
        dg = (t0*b/pf*dpf - g0**2*q*(p%n1 - 1.0_dp)/pf*dpf)/(1.0_dp + q*g0)**2
        tau = sign((1.0_dp - g)/b, ds)
        dtau_dpn = sign((1.0_dp - g)/(b*pf)*dpf - dg/b, ds)
    end subroutine hyperbolic_shear_derivatives

    !> c(2,2) = d s_new / d de of goodman_update, floored where the update is flat (an open
    !> joint's shear, and its normal with the tension cut-off; a joint at the Coulomb cap or
    !> past the hyperbola's asymptote) at ks_residual ks_i: small enough that Newton's
    !> iterations still contract by about that factor there, as the joint's nodes always
    !> belong to the slab's or the body's elements, which keep the matrix regular.
    pure subroutine goodman_update_tangent(p, s, un, de, c)
        type(goodman_params_t), intent(in) :: p
        real(dp), intent(in) :: s(2), un, de(2)
        real(dp), intent(out) :: c(2, 2)
        real(dp) :: sn_mid, sn_new, kn_mid, kn_new, tau, dtau_ds, dtau_dpn, floor
        sn_mid = goodman_normal_stress(p, un + 0.5_dp*de(1))
        sn_new = goodman_normal_stress(p, un + de(1))
        kn_mid = normal_stiffness(p, un + 0.5_dp*de(1))
        kn_new = normal_stiffness(p, un + de(1))
        call hyperbolic_shear_derivatives(p, s(2), de(2), -sn_mid, tau, dtau_ds, dtau_dpn)
        c = 0.0_dp
        c(1, 1) = kn_new
        if (abs(tau) > coulomb_limit(p, sn_new)) then
            ! At the cap tau = sign(tau) max(-sigma_n, 0) tan(phi).
            if (sn_new < 0.0_dp) c(2, 1) = -sign(tan(p%phi*deg), tau)*kn_new
        else
            c(2, 2) = dtau_ds
            c(2, 1) = -0.5_dp*kn_mid*dtau_dpn
        end if
        ! Floors: a small fraction of the joint's initial shear stiffness, so that Newton's
        ! rate of convergence where the update is flat stays of the order ks_residual.
        floor = ks_residual*p%k1*p%gamma_w*(max(-sn_new, p%sigma_n_floor)/p%pa)**p%n1
        c(1, 1) = max(c(1, 1), floor)
        c(2, 2) = max(c(2, 2), floor)
    end subroutine goodman_update_tangent
end module cfrd_goodman
