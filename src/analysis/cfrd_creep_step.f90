!> The creep of one time step at every Gauss point of the active creeping elements
!> (docs/theory.md section 15), by the initial-strain method: the creep strain increment
!> of the step follows from the state at the step's start (cfrd_rockfill_creep: exact in
!> time for that stress), and the stresses relax by D(sigma) d_eps_creep. The out-of-balance
!> force this leaves joins the increment's load, so that the increment's solve turns it
!> into displacements in the same step (the stress update then adds D d_eps of the total
!> strain: sigma_end = sigma + D (d_eps - d_eps_creep)).
module cfrd_creep_step
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, material_t
    use cfrd_assembly, only: element_box_t
    use cfrd_duncan_eb, only: eb_tangent, eb_state_t
    use cfrd_material_law, only: eb_parameters, material_tangent
    use cfrd_rockfill_creep, only: creep_params_t, creep_strain_increment
    implicit none
    private

    public :: creep_relax, creep_parameters

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

    !> Advance the creep of the active creeping elements by dt days: `creep` (ncreep,
    !> ngauss, nelem) grows and `stress` relaxes by the tangent times the creep strain
    !> increment (the law's tangent at the start stress, with its history).
    subroutine creep_relax(model, library, active, dt, stress, strain, history, creep)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        real(dp), intent(in) :: dt
        real(dp), intent(inout) :: stress(:, :, :)
        real(dp), intent(in) :: strain(:, :, :), history(:, :, :)
        real(dp), intent(inout) :: creep(:, :, :)
        real(dp) :: d(4, 4), d_creep(4)
        type(eb_state_t) :: law_state
        integer :: e, ig
        do e = 1, model%mesh%nelem
            if (.not. active(e)) cycle
            associate (mat => model%materials(model%mesh%material(e)))
                if (.not. mat%creep) cycle
                do ig = 1, library(model%mesh%kind(e))%element%gauss_points()
                    ! sigma3 and the stress level of the E-B law at this point
                    call eb_tangent(eb_parameters(mat, model%pa), stress(:, ig, e), &
                                    history(1, ig, e), d, law_state)
                    call creep_strain_increment(creep_parameters(mat, model%pa), &
                                                stress(:, ig, e), law_state%sigma3, &
                                                law_state%level, dt, creep(1, ig, e), &
                                                creep(2, ig, e), d_creep)
                    call material_tangent(mat, model%pa, stress(:, ig, e), strain(:, ig, e), &
                                          history(:, ig, e), d)
                    stress(:, ig, e) = stress(:, ig, e) - matmul(d, d_creep)
                end do
            end associate
        end do
    end subroutine creep_relax
end module cfrd_creep_step
