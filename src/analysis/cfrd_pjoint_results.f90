!> The perimetric joint's displacements per stage (docs/theory.md section 12): for every
!> INTERFACE line of PJOINT material, the relative displacements and tractions of its
!> stations averaged over the line's length. Pure reading of the stage's interface
!> stations; nothing here feeds back into the analysis.
module cfrd_pjoint_results
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, law_pjoint
    use cfrd_results, only: interface_result_t, pjoint_result_t
    use cfrd_joint4, only: joint_frame
    implicit none
    private

    public :: perimetric_joints, pjoint_lines

contains

    !> The line numbers of the INTERFACE lines of PJOINT material, in order of appearance.
    pure function pjoint_lines(model) result(lines)
        type(model_t), intent(in) :: model
        integer, allocatable :: lines(:)
        integer :: k
        allocate (lines(0))
        if (.not. allocated(model%interfaces)) return
        do k = 1, size(model%interfaces)
            associate (e => model%interfaces(k)%element)
                if (model%materials(model%mesh%material(e))%law /= law_pjoint) cycle
            end associate
            if (.not. any(lines == model%interfaces(k)%line)) &
                lines = [lines, model%interfaces(k)%line]
        end do
    end function pjoint_lines

    !> Opening, settlement, shear and mean tractions of each PJOINT line from the stage's
    !> interface stations `stations` (two per element; their mean is the element's mean,
    !> the fields being linear along a joint): length-weighted means over the line.
    subroutine perimetric_joints(model, stations, res)
        type(model_t), intent(in) :: model
        type(interface_result_t), intent(in) :: stations
        type(pjoint_result_t), intent(out) :: res
        real(dp) :: t(2), n(2), length, total
        integer :: j, k, e, nl
        res%line = pjoint_lines(model)
        nl = size(res%line)
        allocate (res%active(nl), source=.true.)
        allocate (res%opening(nl), res%settlement(nl), res%shear(nl), res%sigma_n(nl), &
                  res%tau(nl), source=0.0_dp)
        do j = 1, nl
            total = 0.0_dp
            do k = 1, size(model%interfaces)
                if (model%interfaces(k)%line /= res%line(j)) cycle
                e = model%interfaces(k)%element
                res%active(j) = res%active(j) .and. stations%active(k)
                call joint_frame(model%mesh%x(:, model%mesh%conn(:, e)), t, n, length)
                total = total + length
                res%opening(j) = res%opening(j) + length*sum(stations%du_n(:, k))/2
                res%settlement(j) = res%settlement(j) + length*sum(stations%du_s(:, k))/2
                res%sigma_n(j) = res%sigma_n(j) + length*sum(stations%sigma_n(:, k))/2
                res%tau(j) = res%tau(j) + length*sum(stations%tau(:, k))/2
            end do
            if (total <= 0.0_dp) cycle
            res%opening(j) = res%opening(j)/total
            res%settlement(j) = res%settlement(j)/total
            res%sigma_n(j) = res%sigma_n(j)/total
            res%tau(j) = res%tau(j)/total
        end do
    end subroutine perimetric_joints
end module cfrd_pjoint_results
