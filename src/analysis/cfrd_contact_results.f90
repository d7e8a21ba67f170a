!> What a stage's contact state means to a dam engineer: the tractions, gaps and slips at the
!> slave nodes, and the opening of each slab phase measured directly as the gap (paper
!> Table 5, contact row; docs/theory.md section 14).
module cfrd_contact_results
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t
    use cfrd_results, only: contact_result_t, opening_t
    use cfrd_contact, only: contact_t, contact_open
    use cfrd_contact_view, only: reported_contact
    implicit none
    private

    public :: record_contact, contact_openings, open_gap_limit

    !> A slave node counts as separated when it is open with a gap above this (m).
    real(dp), parameter :: open_gap_limit = 1.0e-6_dp

contains

    !> The contact results of the current state, and the openings per pair and slab phase.
    subroutine record_contact(model, contact, active, result, openings)
        type(model_t), intent(in) :: model
        type(contact_t), intent(in) :: contact
        logical, intent(in) :: active(:)          !! (nelem) elements placed
        type(contact_result_t), intent(out) :: result
        type(opening_t), allocatable, intent(inout) :: openings(:)
        type(contact_t) :: view
        ! (at the card's slave nodes: the slab's where the roles were swapped)
        view = reported_contact(model, contact, active, open_gap_limit)
        result%node = view%node
        result%pair = view%pair
        result%group = view%group
        result%status = view%status
        result%placed = view%placed
        result%x = model%mesh%x(1, view%node)
        result%y = model%mesh%x(2, view%node)
        result%s = view%s
        result%gap = merge(view%gap, 0.0_dp, view%placed)
        result%slip = view%slip
        result%sigma_n = -view%p
        result%tau = view%q
        call contact_openings(model, view, active, result, openings)
    end subroutine record_contact

    !> The opening of each slab phase of each pair: the placed slave segments of one element
    !> group (the group that places the slab phase; nothing before it is placed). The
    !> opening runs from the phase's top end (its highest node) down to the first node that
    !> is not separated (the gap is zero there and positive all the way above it): depth =
    !> its length along the surface, width = its largest gap (paper Table 5). max_gap: the
    !> largest gap anywhere in the phase (also below a closed top).
    subroutine contact_openings(model, contact, active, result, openings)
        type(model_t), intent(in) :: model
        type(contact_t), intent(in) :: contact
        logical, intent(in) :: active(:)
        type(contact_result_t), intent(in) :: result
        type(opening_t), allocatable, intent(inout) :: openings(:)
        logical, allocatable :: member(:)
        integer, allocatable :: order(:)
        integer :: ip, g, k, top, i, c
        type(opening_t) :: opening
        if (.not. allocated(openings)) allocate (openings(0))
        allocate (member(contact%nc))
        do ip = 1, size(model%contact_pairs)
            do g = 0, size(model%mesh%group_name)
                member = .false.
                do k = 1, size(contact%seg, 2)
                    if (contact%pair(contact%seg(1, k)) /= ip) cycle
                    if (model%mesh%group(contact%seg_element(k)) /= g) cycle
                    if (.not. active(contact%seg_element(k))) cycle
                    member(contact%seg(:, k)) = .true.
                end do
                if (.not. any(member)) cycle
                opening = opening_t(line=ip, group=g)
                order = pack([(c, c=1, contact%nc)], member)
                call sort_by_s(order)
                top = order(size(order))
                opening%top = model%mesh%x(:, contact%node(top))
                opening%length = contact%s(top) - contact%s(order(1))
                if (any(contact%placed(order))) then
                    ! (a closed node's gap is zero up to round-off: not an opening)
                    opening%max_gap = 0.0_dp
                    do i = 1, size(order)
                        if (separated(order(i))) opening%max_gap = max(opening%max_gap, &
                                                                       result%gap(order(i)))
                    end do
                    opening%max_compression = min(0.0_dp, minval(result%sigma_n(order)))
                    ! The opening from the top: down to the first node in contact.
                    do i = size(order), 1, -1
                        c = order(i)
                        if (.not. separated(c)) exit
                        opening%width = max(opening%width, result%gap(c))
                    end do
                    if (i < size(order)) then
                        opening%depth = contact%s(top) - contact%s(order(max(i, 1)))
                    end if
                end if
                openings = [openings, opening]
            end do
        end do
    contains
        pure logical function separated(c)
            integer, intent(in) :: c
            separated = contact%placed(c) .and. contact%status(c) == contact_open .and. &
                        result%gap(c) > open_gap_limit
        end function separated

        subroutine sort_by_s(list)
            integer, intent(inout) :: list(:)
            integer :: a, b, key
            do a = 2, size(list)
                key = list(a)
                b = a - 1
                do while (b >= 1)
                    if (contact%s(list(b)) <= contact%s(key)) exit
                    list(b + 1) = list(b)
                    b = b - 1
                end do
                list(b + 1) = key
            end do
        end subroutine sort_by_s
    end subroutine contact_openings
end module cfrd_contact_results
