!> The one place where a material law is chosen: the tangent matrix at an integration point
!> from its stress, total strain and history, the stress update over a strain increment,
!> its derivative (Newton's tangent), and the history update after an accepted increment.
!> History lives in a plain array per point, so the state needs no knowledge of the laws.
!> Stress and strain are 4-vectors (xx, yy, zz, xy) for solids; a joint uses components 1-2
!> for (sigma_n, tau) and (du_n, du_s) and leaves 3-4 at zero.
module cfrd_material_law
    use cfrd_kinds, only: dp
    use cfrd_model, only: material_t, law_elastic, law_duncan_eb, law_goodman, law_pjoint
    use cfrd_elastic, only: elastic_dmatrix
    use cfrd_duncan_eb, only: eb_params_t, eb_tangent, eb_stress_state, eb_state_t, &
                              eb_moduli_gradient
    use cfrd_goodman, only: goodman_params_t, goodman_tangent, goodman_update, &
                            goodman_update_tangent
    use cfrd_pjoint, only: pjoint_params_t, pjoint_stress, pjoint_tangent
    implicit none
    private

    public :: nhistory, material_tangent, material_update, material_update_tangent
    public :: update_history, is_linear, eb_parameters, goodman_parameters, stress_level

    !> History values per Gauss point. E-B: (1) past maximum of Duncan's stress-state
    !> function, (2) past maximum of the stress level.
    integer, parameter :: nhistory = 2

contains

    !> Whether the law's tangent is constant (then one factorisation serves a whole stage).
    pure logical function is_linear(mat)
        type(material_t), intent(in) :: mat
        is_linear = mat%law == law_elastic
    end function is_linear

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
    !> when the caller has it (Newton keeps it over an increment's iterations).
    pure subroutine material_update(mat, pa, stress, strain, history, de, midpoint, &
                                    stress_new, stress_mid, d_start)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4), strain(4), history(nhistory), de(4)
        logical, intent(in) :: midpoint
        real(dp), intent(out) :: stress_new(4), stress_mid(4)
        real(dp), intent(in), optional :: d_start(4, 4)
        real(dp) :: d(4, 4)
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
        stress_mid = stress + 0.5_dp*matmul(d, de)
        if (midpoint) call material_tangent(mat, pa, stress_mid, strain + 0.5_dp*de, &
                                            history, d)
        stress_new = stress + matmul(d, de)
    end subroutine material_update

    !> d stress_new / d de of the midpoint update (Newton's tangent; docs/theory.md section
    !> 9, "Consistent tangent"). E-B: with sigma_mid = sigma + D(sigma) de/2 and
    !> stress_new = sigma + D(sigma_mid) de,
    !>     C = D(sigma_mid) + [d(D(s) de)/ds at s = sigma_mid] D(sigma)/2,
    !> where D(s) de = Bt tr(de) m + Gt P de (m = (1, 1, 1, 0), P the deviatoric projector
    !> of section 2, Gt = 3 Bt Et / (9 Bt - Et)) and the moduli's gradients come from
    !> eb_moduli_gradient; not symmetric in general. The Goodman law differentiates its exact
    !> update (goodman_update_tangent), with floors that keep the matrix regular where a
    !> joint slips or opens. A linear law's update is linear: C = D. d_start: D(sigma) when
    !> the caller has it.
    pure subroutine material_update_tangent(mat, pa, stress, strain, history, de, c, d_start)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4), strain(4), history(nhistory), de(4)
        real(dp), intent(out) :: c(4, 4)
        real(dp), intent(in), optional :: d_start(4, 4)
        real(dp), parameter :: m(4) = [1.0_dp, 1.0_dp, 1.0_dp, 0.0_dp]
        real(dp) :: d0(4, 4), mid(4), et, bt, det(4), dbt(4), dgt(4), nine_b_e
        real(dp) :: pde(4), trace, dsigma(4, 4)
        integer :: j
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
            mid = stress + 0.5_dp*matmul(d0, de)
            call eb_moduli_gradient(eb_parameters(mat, pa), mid, history(1), et, bt, det, dbt)
            c = elastic_dmatrix(et, (3.0_dp*bt - et)/(6.0_dp*bt))
            ! d(D(s) de)/ds = m tr(de) dBt^T + (P de) dGt^T
            nine_b_e = 9.0_dp*bt - et
            dgt = (27.0_dp*bt**2*det - 3.0_dp*et**2*dbt)/nine_b_e**2
            trace = de(1) + de(2) + de(3)
            pde(1:3) = 2.0_dp*de(1:3) - 2.0_dp/3.0_dp*trace
            pde(4) = de(4)
            do j = 1, 4
                dsigma(:, j) = m*trace*dbt(j) + pde*dgt(j)
            end do
            c = c + 0.5_dp*matmul(dsigma, d0)
        case default
            call material_tangent(mat, pa, stress, strain, history, c)
        end select
    end subroutine material_update_tangent

    !> Stress level S of a Gauss point (0 for laws without one).
    pure real(dp) function stress_level(mat, pa, stress, history) result(level)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4), history(nhistory)
        type(eb_state_t) :: state
        real(dp) :: d(4, 4)
        level = 0.0_dp
        if (mat%law /= law_duncan_eb) return
        call eb_tangent(eb_parameters(mat, pa), stress, history(1), d, state)
        level = state%level
    end function stress_level

    !> Raise the history maxima after an accepted increment. Without unloading (EFFECTS
    !> UNLOAD OFF) the past maximum of the stress state stays 0: the law always loads.
    pure subroutine update_history(mat, pa, stress, history)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4)
        real(dp), intent(inout) :: history(nhistory)
        if (mat%law /= law_duncan_eb) return
        if (mat%unload) history(1) = max(history(1), &
                                         eb_stress_state(eb_parameters(mat, pa), stress))
        history(2) = max(history(2), stress_level(mat, pa, stress, history))
    end subroutine update_history
end module cfrd_material_law
