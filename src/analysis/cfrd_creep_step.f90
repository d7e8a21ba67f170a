!> The creep of one time step at every Gauss point of the active creeping elements
!> (docs/theory.md section 15), by the initial-strain method: the creep strain increment
!> d_eps_c of the step follows from the state at the step's start (cfrd_rockfill_creep:
!> exact in time for that stress). The increment's solve takes the load D d_eps_c (the
!> stresses the creep would relax) into its out-of-balance force, and the stress update
!> integrates the law over the mechanical strain d_eps - d_eps_c from the start stress:
!> where the loads fix the stresses, the strain increment is then the creep strain whatever
!> the tangent (no artificial excursion of a stress-dependent tangent).
module cfrd_creep_step
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, material_t, law_duncan_eb
    use cfrd_assembly, only: element_box_t
    use cfrd_duncan_eb, only: eb_tangent, eb_state_t, eb_level_state
    use cfrd_material_law, only: eb_parameters, material_tangent
    use cfrd_rockfill_creep, only: creep_params_t, creep_strain_increment, final_strain_step
    implicit none
    private

    public :: creep_strains, creep_parameters, wetting_strains, wetting_parameters

    !> Creep state per Gauss point: (1) volumetric and (2) generalised shear creep strain
    !> reached, compression positive.
    integer, parameter, public :: ncreep = 2

contains

    !> The creep parameters of a material card, with the deck's atmospheric pressure.
    pure function creep_parameters(mat, pa) result(p)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa
        type(creep_params_t) :: p
        p = creep_params_t(alpha=mat%creep_alpha, b=mat%creep_b, mc=mat%creep_mc, &
                           d=mat%creep_d, l=mat%creep_l, pa=pa)
    end function creep_parameters

    !> The wetting parameters of a material card in the form of the creep law's final
    !> strains (b = CW, mc = NW, d = DW, l = 1: Shen's wetting model, docs/theory.md s. 16).
    pure function wetting_parameters(mat, pa) result(p)
        type(material_t), intent(in) :: mat
        real(dp), intent(in) :: pa
        type(creep_params_t) :: p
        p = creep_params_t(alpha=0.0_dp, b=mat%wet_c, mc=mat%wet_n, d=mat%wet_d, &
                           l=1.0_dp, pa=pa)
    end function wetting_parameters

    !> Advance the creep of the active creeping elements by dt days: `creep` (ncreep,
    !> ngauss, nelem) grows; creep_stress (4, ngauss, nelem) gets the stresses the step's
    !> creep strain would relax, D d_eps_c with the law's tangent at the start stress and
    !> history (zero where nothing creeps).
    subroutine creep_strains(model, library, active, dt, stress, strain, history, creep, &
                             creep_stress)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        real(dp), intent(in) :: dt
        real(dp), intent(in) :: stress(:, :, :), strain(:, :, :), history(:, :, :)
        real(dp), intent(inout) :: creep(:, :, :)
        real(dp), intent(out) :: creep_stress(:, :, :)
        creep_stress = 0.0_dp
        call relaxed_stresses(model, library, active, .false., dt, stress, strain, history, &
                              creep, creep_stress)
    end subroutine creep_strains

    !> The wetting collapse of the elements of `wetting` (a WET stage) over one increment:
    !> the share `share` of what remains of their wetting strains (final values at the
    !> start stress less the strain reached, `wet`) is taken, and its relaxed stresses
    !> D d_eps_w are added to creep_stress (the load of the increment, as for creep).
    subroutine wetting_strains(model, library, wetting, share, stress, strain, history, wet, &
                               creep_stress)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: wetting(:)
        real(dp), intent(in) :: share
        real(dp), intent(in) :: stress(:, :, :), strain(:, :, :), history(:, :, :)
        real(dp), intent(inout) :: wet(:, :, :)
        real(dp), intent(inout) :: creep_stress(:, :, :)
        call relaxed_stresses(model, library, wetting, .true., share, stress, strain, &
                              history, wet, creep_stress)
    end subroutine wetting_strains

    !> At every point of the elements of `mask` whose material creeps (or, with `wetting`,
    !> collapses on wetting): the step of the law from the strains `reached` (dt days of
    !> creep, or the share `amount` of the wetting that remains), and D times its strain
    !> added to creep_stress, D the law's tangent at the start stress and history.
    subroutine relaxed_stresses(model, library, mask, wetting, amount, stress, strain, &
                                history, reached, creep_stress)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: mask(:), wetting
        real(dp), intent(in) :: amount
        real(dp), intent(in) :: stress(:, :, :), strain(:, :, :), history(:, :, :)
        real(dp), intent(inout) :: reached(:, :, :)
        real(dp), intent(inout) :: creep_stress(:, :, :)
        real(dp) :: d(4, 4), d_strain(4), bulk, shear, sigma3, level, ss
        type(eb_state_t) :: law_state
        integer :: e, ig
        do e = 1, model%mesh%nelem
            if (.not. mask(e)) cycle
            associate (mat => model%materials(model%mesh%material(e)))
                if (.not. merge(mat%wetting, mat%creep, wetting)) cycle
                do ig = 1, library(model%mesh%kind(e))%element%gauss_points()
                    ! sigma3 and the stress level of the E-B law at this point, and the
                    ! tangent that relaxes the stresses (its bulk and shear moduli): an E-B
                    ! material's from the one evaluation of the law; a material EFFECTS
                    ! ROCKFILL LINEAR made elastic keeps its E-B state (the creep law's
                    ! input) but relaxes by its own elastic tangent, the stiffness it is
                    ! solved with (the E-B tangent there is not a duplicate: far softer,
                    ! docs/robustness.md, "The empty row update")
                    if (mat%law == law_duncan_eb) then
                        call eb_tangent(eb_parameters(mat, model%pa), stress(:, ig, e), &
                                        history(1, ig, e), d, law_state)
                        sigma3 = law_state%sigma3
                        level = law_state%level
                    else
                        call eb_level_state(eb_parameters(mat, model%pa), stress(:, ig, e), &
                                            level, ss, sigma3)
                        call material_tangent(mat, model%pa, stress(:, ig, e), &
                                              strain(:, ig, e), history(:, ig, e), d)
                    end if
                    bulk = (d(1, 1) + 2.0_dp*d(1, 2))/3.0_dp
                    shear = d(4, 4)
                    if (wetting) then
                        call final_strain_step(wetting_parameters(mat, model%pa), &
                                               stress(:, ig, e), sigma3, &
                                               level, amount, reached(1, ig, e), &
                                               reached(2, ig, e), d_strain, bulk, shear)
                    else
                        call creep_strain_increment(creep_parameters(mat, model%pa), &
                                                    stress(:, ig, e), sigma3, &
                                                    level, amount, &
                                                    reached(1, ig, e), reached(2, ig, e), &
                                                    d_strain, bulk, shear)
                    end if
                    creep_stress(:, ig, e) = creep_stress(:, ig, e) + matmul(d, d_strain)
                end do
            end associate
        end do
    end subroutine relaxed_stresses
end module cfrd_creep_step
