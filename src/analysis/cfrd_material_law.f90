!> The one place where a material law is chosen: the tangent matrix at an integration point
!> from its stress, total strain and history, the stress update over a strain increment,
!> its derivative (Newton's tangent), and the history update after an accepted increment.
!> History lives in a plain array per point, so the state needs no knowledge of the laws.
!> Stress and strain are 4-vectors (xx, yy, zz, xy) for solids; a joint uses components 1-2
!> for (sigma_n, tau) and (du_n, du_s) and leaves 3-4 at zero.
module cfrd_material_law
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, material_t, law_elastic, law_duncan_eb, law_goodman, law_pjoint
    use cfrd_elastic, only: elastic_dmatrix
    use cfrd_duncan_eb, only: eb_params_t, eb_tangent, eb_level_state, eb_moduli_gradient, &
                              eb_substeps
    use cfrd_goodman, only: goodman_params_t, goodman_tangent, goodman_update, &
                            goodman_update_tangent
    use cfrd_pjoint, only: pjoint_params_t, pjoint_stress, pjoint_tangent
    implicit none
    private

    public :: nhistory, material_tangent, material_update, material_update_tangent
    public :: material_update_with_tangent
    public :: update_history, is_linear, all_linear, eb_parameters, goodman_parameters, stress_level
    public :: update_substeps, max_substeps

    !> History values per Gauss point. E-B: (1) past maximum of Duncan's stress-state
    !> function, (2) past maximum of the stress level.
    integer, parameter :: nhistory = 2
    !> Sub-steps of the E-B update under Newton (docs/theory.md section 9, "Sub-steps"): a
    !> sub-step may take its half-way stress level at most this share of the way to the
    !> limit point of the one-step midpoint rule [choice] ...
    real(dp), parameter :: substep_reach = 0.125_dp
    !> ... with at most this many sub-steps per point and increment [choice].
    integer, parameter :: max_substeps = 64

contains

    !> Whether the law's tangent is constant (then one factorisation serves a whole stage).
    pure logical function is_linear(mat)
        type(material_t), intent(in) :: mat
        is_linear = mat%law == law_elastic
    end function is_linear

    !> Whether every active element's law is linear: the tangent of the active set is
    !> constant, factorised once per pattern (cfrd_increment; CHOLMOD's ordering,
    !> cfrd_linear_system).
    pure logical function all_linear(model, active)
        type(model_t), intent(in) :: model
        logical, intent(in) :: active(:)
        integer :: e
        all_linear = .true.
        do e = 1, model%mesh%nelem
            if (.not. active(e)) cycle
            if (.not. is_linear(model%materials(model%mesh%material(e)))) then
                all_linear = .false.
                return
            end if
        end do
    end function all_linear

    !> The E-B parameters of a material card, with the deck's atmospheric pressure.
    pure function eb_parameters(mat, pa) result(p)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa
        type(eb_params_t) :: p
        p = eb_params_t(k=mat%k_modulus, n=mat%n_exponent, rf=mat%failure_ratio, &
                        kb=mat%k_bulk, m=mat%m_exponent, phi0=mat%phi0, dphi=mat%dphi, &
                        cohesion=mat%cohesion, kur=mat%k_unload, pa=pa, &
                        sigma3_floor=mat%sigma3_floor)
    end function eb_parameters

    !> The Goodman parameters of a material card, with the deck's atmospheric pressure.
    pure function goodman_parameters(mat, pa) result(p)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa
        type(goodman_params_t) :: p
        p = goodman_params_t(kn_compression=mat%kn_compression, kn_tension=mat%kn_tension, &
                             k1=mat%k1, n1=mat%n1, rf1=mat%rf1, phi=mat%phi, &
                             gamma_w=mat%gamma_w, pa=pa, sigma_n_floor=mat%sigma_n_floor, &
                             tension_cutoff=mat%tension_cutoff)
    end function goodman_parameters

    !> The perimetric-joint parameters of a material card.
    pure function pjoint_parameters(mat) result(p)
        type(material_t), intent(in) :: mat
        type(pjoint_params_t) :: p
        p = pjoint_params_t(kn_compression=mat%kn_compression, kn_tension=mat%kn_tension, &
                            ks=mat%ks_joint)
    end function pjoint_parameters

    !> Tangent matrix d(4,4) at stress (tension positive), total strain and history.
    pure subroutine material_tangent(mat, pa, stress, strain, history, d)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4), strain(4), history(nhistory)
        real(dp), intent(out) :: d(4, 4)
        real(dp) :: d2(2, 2)
        select case (mat%law)
        case (law_duncan_eb)
            call eb_tangent(eb_parameters(mat, pa), stress, history(1), d)
        case (law_goodman)
            d = 0.0_dp
            call goodman_tangent(goodman_parameters(mat, pa), stress(1:2), strain(1), d2)
            d(1:2, 1:2) = d2
        case (law_pjoint)
            d = 0.0_dp
            call pjoint_tangent(pjoint_parameters(mat), strain(1:2), d2)
            d(1:2, 1:2) = d2
        case default
            d = elastic_dmatrix(mat%youngs_modulus, mat%poisson_ratio)
        end select
    end subroutine material_tangent

    !> Stress after the strain increment de from (stress, strain, history): with `midpoint`
    !> sigma + D(sigma + D(sigma) de/2) de, else sigma + D(sigma) de (docs/theory.md
    !> section 9); the Goodman law updates its normal traction exactly and caps the shear
    !> at the Coulomb limit (section 12). stress_mid: the half-way stress. d_start: D(sigma)
    !> when the caller has it (Newton keeps it over an increment's iterations). substeps:
    !> the E-B midpoint update in that many equal sub-steps of de (Newton, update_substeps);
    !> stress_mid is then the stress half-way along the sub-steps.
    pure subroutine material_update(mat, pa, stress, strain, history, de, midpoint, &
                                    stress_new, stress_mid, d_start, substeps)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4), strain(4), history(nhistory), de(4)
        logical, intent(in) :: midpoint
        real(dp), intent(out) :: stress_new(4), stress_mid(4)
        real(dp), intent(in), optional :: d_start(4, 4)
        integer, intent(in), optional :: substeps
        real(dp) :: d(4, 4), h(4), mid(4)
        integer :: nsub, k
        if (mat%law == law_goodman) then
            stress_new = 0.0_dp
            stress_mid = 0.0_dp
            call goodman_update(goodman_parameters(mat, pa), stress(1:2), strain(1), de(1:2), &
                                midpoint, stress_new(1:2), stress_mid(1:2))
            return
        end if
        if (mat%law == law_pjoint) then
            ! Elastic and bilinear: exact from the total relative displacements.
            stress_new = 0.0_dp
            stress_mid = 0.0_dp
            stress_new(1:2) = pjoint_stress(pjoint_parameters(mat), strain(1:2) + de(1:2))
            stress_mid(1:2) = pjoint_stress(pjoint_parameters(mat), &
                                            strain(1:2) + 0.5_dp*de(1:2))
            return
        end if
        if (present(d_start)) then
            d = d_start
        else
            call material_tangent(mat, pa, stress, strain, history, d)
        end if
        nsub = 1
        if (present(substeps) .and. midpoint .and. mat%law == law_duncan_eb) nsub = substeps
        if (nsub > 1) then
            ! sigma_k+1 = sigma_k + D(sigma_k + D(sigma_k) h/2) h, h = de / nsub
            h = de/nsub
            stress_new = stress
            do k = 1, nsub
                if (k > 1) call material_tangent(mat, pa, stress_new, strain, history, d)
                mid = stress_new + 0.5_dp*matmul(d, h)
                call material_tangent(mat, pa, mid, strain, history, d)
                if (2*k - 1 == nsub) stress_mid = mid   ! odd: the middle sub-step's half-way
                stress_new = stress_new + matmul(d, h)
                if (2*k == nsub) stress_mid = stress_new   ! even: after half the sub-steps
            end do
            return
        end if
        stress_mid = stress + 0.5_dp*matmul(d, de)
        if (midpoint) call material_tangent(mat, pa, stress_mid, strain + 0.5_dp*de, &
                                            history, d)
        stress_new = stress + matmul(d, de)
    end subroutine material_update

    !> d stress_new / d de of the midpoint update (Newton's tangent; docs/theory.md section
    !> 9, "Consistent tangent"). E-B: with sigma_mid = sigma + D(sigma) de/2 and
    !> stress_new = sigma + D(sigma_mid) de,
    !>     C = D(sigma_mid) + [d(D(s) de)/ds at s = sigma_mid] D(sigma)/2
    !> (eb_response); with `substeps` the chain rule through the sub-steps of
    !> material_update. Not symmetric in general. The Goodman law differentiates its exact
    !> update (goodman_update_tangent), with floors that keep the matrix regular where a
    !> joint slips or opens. A linear law's update is linear: C = D. d_start: D(sigma) when
    !> the caller has it.
    pure subroutine material_update_tangent(mat, pa, stress, strain, history, de, c, d_start, &
                                            substeps)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4), strain(4), history(nhistory), de(4)
        real(dp), intent(out) :: c(4, 4)
        real(dp), intent(in), optional :: d_start(4, 4)
        integer, intent(in), optional :: substeps
        real(dp) :: d0(4, 4), mid(4), dsigma(4, 4)
        integer :: nsub
        select case (mat%law)
        case (law_goodman)
            c = 0.0_dp
            call goodman_update_tangent(goodman_parameters(mat, pa), stress(1:2), strain(1), &
                                        de(1:2), c(1:2, 1:2))
        case (law_pjoint)
            ! The derivative of the exact update: the tangent at the increment's end.
            c = 0.0_dp
            call pjoint_tangent(pjoint_parameters(mat), strain(1:2) + de(1:2), c(1:2, 1:2))
        case (law_duncan_eb)
            if (present(d_start)) then
                d0 = d_start
            else
                call eb_tangent(eb_parameters(mat, pa), stress, history(1), d0)
            end if
            nsub = 1
            if (present(substeps)) nsub = substeps
            if (nsub > 1) then
                call substep_tangent(eb_parameters(mat, pa), stress, history(1), de, d0, nsub, c)
                return
            end if
            mid = stress + 0.5_dp*matmul(d0, de)
            call eb_response(eb_parameters(mat, pa), mid, history(1), de, c, dsigma)
            c = c + 0.5_dp*matmul(dsigma, d0)
        case default
            call material_tangent(mat, pa, stress, strain, history, c)
        end select
    end subroutine material_update_tangent

    !> D(s) and g = d(D(s) v)/ds of the E-B law at stress s: with D(s) v = Bt tr(v) m +
    !> Gt P v (m = (1, 1, 1, 0), P the deviatoric projector of section 2, Gt = 3 Bt Et /
    !> (9 Bt - Et)), g = m tr(v) dBt^T + (P v) dGt^T, the moduli's gradients from
    !> eb_moduli_gradient.
    pure subroutine eb_response(p, s, ss_max, v, d, g)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: s(4), ss_max, v(4)
        real(dp), intent(out) :: d(4, 4), g(4, 4)
        real(dp), parameter :: m(4) = [1.0_dp, 1.0_dp, 1.0_dp, 0.0_dp]
        real(dp) :: et, bt, det(4), dbt(4), dgt(4), nine_b_e, pv(4), trace
        integer :: j
        call eb_moduli_gradient(p, s, ss_max, et, bt, det, dbt)
        d = elastic_dmatrix(et, (3.0_dp*bt - et)/(6.0_dp*bt))
        nine_b_e = 9.0_dp*bt - et
        dgt = (27.0_dp*bt**2*det - 3.0_dp*et**2*dbt)/nine_b_e**2
        trace = v(1) + v(2) + v(3)
        pv(1:3) = 2.0_dp*v(1:3) - 2.0_dp/3.0_dp*trace
        pv(4) = v(4)
        do j = 1, 4
            g(:, j) = m*trace*dbt(j) + pv*dgt(j)
        end do
    end subroutine eb_response

    !> d sigma_n / d de of the E-B midpoint update in n sub-steps h = de/n (material_update):
    !> with A_k = d sigma_k / d de (A_0 = 0), mid_k = sigma_k + D(sigma_k) h/2 and
    !> sigma_k+1 = sigma_k + D(mid_k) h,
    !>     d mid_k = A_k + g(sigma_k, h/2) A_k + D(sigma_k)/(2n),
    !>     A_k+1 = A_k + g(mid_k, h) d mid_k + D(mid_k)/n       (docs/theory.md section 9).
    !> `stress_new`, `stress_mid`: the update's own states (sigma_n, and the half-way stress
    !> as material_update returns it), with D(s) from eb_response.
    pure subroutine substep_tangent(p, stress, ss_max, de, d0, n, a, stress_new, stress_mid)
        type(eb_params_t), intent(in) :: p
        real(dp), intent(in) :: stress(4), ss_max, de(4), d0(4, 4)
        integer, intent(in) :: n
        real(dp), intent(out) :: a(4, 4)
        real(dp), intent(out), optional :: stress_new(4), stress_mid(4)
        real(dp) :: h(4), s(4), mid(4), d(4, 4), g(4, 4), dmid(4, 4), dm(4, 4), gm(4, 4)
        integer :: k
        h = de/n
        s = stress
        a = 0.0_dp
        do k = 1, n
            if (k == 1) then
                d = d0
                dmid = d0/(2.0_dp*n)
            else
                call eb_response(p, s, ss_max, 0.5_dp*h, d, g)
                dmid = a + matmul(g, a) + d/(2.0_dp*n)
            end if
            mid = s + 0.5_dp*matmul(d, h)
            call eb_response(p, mid, ss_max, h, dm, gm)
            a = a + matmul(gm, dmid) + dm/n
            if (present(stress_mid) .and. 2*k - 1 == n) stress_mid = mid
            s = s + matmul(dm, h)
            if (present(stress_mid) .and. 2*k == n) stress_mid = s
        end do
        if (present(stress_new)) stress_new = s
    end subroutine substep_tangent

    !> material_update (midpoint, `substeps` sub-steps, d_start) and material_update_tangent
    !> of one point in one pass, for Newton's line search: stress_new, stress_mid and
    !> c = d stress_new / d de. For the E-B law the update's states are those of the
    !> tangent's recursion (substep_tangent, n >= 1), so the law is evaluated once per state
    !> instead of once for the update and once for its derivative; its D(s) comes from
    !> eb_moduli_gradient's moduli, which are eb_tangent's to round-off. The other laws
    !> update as material_update does.
    pure subroutine material_update_with_tangent(mat, pa, stress, strain, history, de, d_start, &
                                                 substeps, stress_new, stress_mid, c)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4), strain(4), history(nhistory), de(4)
        real(dp), intent(in) :: d_start(4, 4)
        integer, intent(in) :: substeps
        real(dp), intent(out) :: stress_new(4), stress_mid(4), c(4, 4)
        if (mat%law == law_duncan_eb) then
            call substep_tangent(eb_parameters(mat, pa), stress, history(1), de, d_start, &
                                 max(1, substeps), c, stress_new, stress_mid)
        else
            call material_update(mat, pa, stress, strain, history, de, .true., stress_new, &
                                 stress_mid, d_start, substeps)
            call material_update_tangent(mat, pa, stress, strain, history, de, c, d_start, &
                                         substeps)
        end if
    end subroutine material_update_with_tangent

    !> Sub-steps of the E-B midpoint update over de from `stress` under Newton (docs/theory.md
    !> section 9, "Sub-steps"): where one step of the midpoint rule would come near its
    !> limit point (eb_substeps, from the forward Euler prediction with d_start = D(stress)),
    !> enough equal sub-steps that none does; 1 for the other laws, at most max_substeps.
    pure integer function update_substeps(mat, pa, stress, history, de, d_start) result(n)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4), history(nhistory), de(4), d_start(4, 4)
        real(dp) :: x
        n = 1
        if (mat%law /= law_duncan_eb) return
        x = eb_substeps(eb_parameters(mat, pa), stress, history(1), &
                        stress + matmul(d_start, de), substep_reach)
        if (x >= max_substeps) then
            n = max_substeps
        else if (x > 1.0_dp) then
            n = ceiling(x)
        end if
    end function update_substeps

    !> Stress level S of a Gauss point (0 for laws without one).
    pure real(dp) function stress_level(mat, pa, stress) result(level)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4)
        real(dp) :: ss
        level = 0.0_dp
        if (mat%law /= law_duncan_eb) return
        call eb_level_state(eb_parameters(mat, pa), stress, level, ss)
    end function stress_level

    !> Raise the history maxima after an accepted increment. Without unloading (EFFECTS
    !> UNLOAD OFF) the past maximum of the stress state stays 0: the law always loads.
    !> The level and the stress state from one evaluation of the law (eb_level_state).
    pure subroutine update_history(mat, pa, stress, history)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4)
        real(dp), intent(inout) :: history(nhistory)
        real(dp) :: level, ss
        if (mat%law /= law_duncan_eb) return
        call eb_level_state(eb_parameters(mat, pa), stress, level, ss)
        if (mat%unload) history(1) = max(history(1), ss)
        history(2) = max(history(2), level)
    end subroutine update_history
end module cfrd_material_law
