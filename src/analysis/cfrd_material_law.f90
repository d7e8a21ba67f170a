!> The one place where a material law is chosen: the tangent matrix at a Gauss point from its
!> stress and history, and the history update after an accepted increment. History lives in a
!> plain array per Gauss point, so the state needs no knowledge of the laws.
module cfrd_material_law
    use cfrd_kinds, only: dp
    use cfrd_model, only: material_t, law_elastic, law_duncan_eb
    use cfrd_elastic, only: elastic_dmatrix
    use cfrd_duncan_eb, only: eb_params_t, eb_tangent, eb_stress_state, eb_state_t
    implicit none
    private

    public :: nhistory, material_tangent, update_history, is_linear, eb_parameters
    public :: stress_level

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

    !> Tangent matrix d(4,4) for stress (xx, yy, zz, xy; tension positive) and history.
    pure subroutine material_tangent(mat, pa, stress, history, d)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4), history(nhistory)
        real(dp), intent(out) :: d(4, 4)
        select case (mat%law)
        case (law_duncan_eb)
            call eb_tangent(eb_parameters(mat, pa), stress, history(1), d)
        case default
            d = elastic_dmatrix(mat%youngs_modulus, mat%poisson_ratio)
        end select
    end subroutine material_tangent

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

    !> Raise the history maxima after an accepted increment.
    pure subroutine update_history(mat, pa, stress, history)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4)
        real(dp), intent(inout) :: history(nhistory)
        if (mat%law /= law_duncan_eb) return
        history(1) = max(history(1), eb_stress_state(eb_parameters(mat, pa), stress))
        history(2) = max(history(2), stress_level(mat, pa, stress, history))
    end subroutine update_history
end module cfrd_material_law
