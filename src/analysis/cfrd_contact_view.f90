!> The contact state as the results report it (docs/results.md, contact): at the slave
!> nodes of each pair as the card gives them. Where the roles were swapped (a slab much finer
!> than the cushion made the master, cfrd_contact_roles), the multipliers sit at the
!> cushion's nodes, and the results are evaluated at the slab's nodes: each slab node's gap is
!> its distance from the nearest active cushion face along that face's normal (+ open), its
!> pressure, shear and slip are those of the cushion nodes interpolated linearly along that
!> face (the face's shape functions at the slab node's projection), and its status is that of
!> the face's nodes (both open: open; both closed: the nearer one's; one of each: open where
!> the gap exceeds the separation limit, else the closed one's). The phase openings, tables
!> and figures then read the slab's nodes as before.
module cfrd_contact_view
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t
    use cfrd_contact, only: contact_t, contact_open, arc_lengths
    use cfrd_mortar, only: face_normal, closest_on_face
    implicit none
    private

    public :: reported_contact

contains

    !> `contact` as reported: a copy where no pair is swapped; else the unswapped pairs' slave
    !> nodes as they are and the swapped pairs' master (slab) nodes with the values above.
    !> Only the fields the results read are set (node, pair, group, s, seg, seg_element,
    !> placed, status, p, q, gap, slip).
    function reported_contact(model, contact, active, open_limit) result(view)
        type(model_t), intent(in) :: model
        type(contact_t), intent(in) :: contact
        logical, intent(in) :: active(:)           !! (nelem) elements placed
        real(dp), intent(in) :: open_limit         !! m, a gap above it is separated
        type(contact_t) :: view
        integer, allocatable :: index_of(:), cseg(:, :)
        real(dp), allocatable :: x(:, :), half(:)
        integer :: ip, k, c, j, nv, ns, nf
        if (.not. any(model%contact_pairs%swapped)) then
            view = contact
            return
        end if
        x = model%mesh%x + contact%u
        allocate (view%node(0), view%pair(0), view%group(0), view%status(0), view%p(0), &
                  view%q(0), view%gap(0), view%slip(0), view%placed(0))
        allocate (view%seg(2, 0), view%seg_element(0))
        allocate (index_of(model%mesh%nnode))
        do ip = 1, size(model%contact_pairs)
            index_of = 0
            if (.not. model%contact_pairs(ip)%swapped) then
                do k = 1, size(contact%seg, 2)
                    if (contact%pair(contact%seg(1, k)) /= ip) cycle
                    call add_face(contact%node(contact%seg(:, k)), contact%seg_element(k))
                end do
                do c = 1, contact%nc
                    if (contact%pair(c) /= ip .or. index_of(contact%node(c)) == 0) cycle
                    j = index_of(contact%node(c))
                    view%status(j) = contact%status(c)
                    view%placed(j) = contact%placed(c)
                    view%p(j) = contact%p(c)
                    view%q(j) = contact%q(c)
                    view%gap(j) = contact%gap(c)
                    view%slip(j) = contact%slip(c)
                end do
                cycle
            end if
            ! the active slave (cushion) faces of the pair, as contact nodes
            cseg = reshape([integer ::], [2, 0])
            do k = 1, size(contact%seg, 2)
                if (contact%pair(contact%seg(1, k)) /= ip) cycle
                if (active(contact%seg_element(k))) cseg = reshape([cseg, contact%seg(:, k)], &
                                                                   [2, size(cseg, 2) + 1])
            end do
            ns = size(view%node)
            nf = size(view%seg, 2)
            do k = 1, size(contact%mseg, 2)
                if (contact%mseg_pair(k) /= ip) cycle
                call add_face(contact%mseg(:, k), contact%mseg_element(k))
                if (.not. active(contact%mseg_element(k))) cycle
                view%placed(index_of(contact%mseg(:, k))) = .true.
            end do
            ! half the length of a reported node's active faces, the larger one
            allocate (half(size(view%node)), source=0.0_dp)
            do k = nf + 1, size(view%seg, 2)
                if (.not. active(view%seg_element(k))) cycle
                half(view%seg(:, k)) = max(half(view%seg(:, k)), 0.5_dp* &
                                           norm2(x(:, view%node(view%seg(2, k))) - &
                                                 x(:, view%node(view%seg(1, k)))))
            end do
            do j = ns + 1, size(view%node)
                if (view%placed(j)) call evaluate(j, cseg)
            end do
            deallocate (half)
        end do
        view%nc = size(view%node)
        view%s = arc_lengths(model, view)
    contains
        !> A face of the reported surface (mesh nodes `ends`), its nodes made on first sight.
        subroutine add_face(ends, element)
            integer, intent(in) :: ends(2), element
            integer :: i, idx(2)
            do i = 1, 2
                if (index_of(ends(i)) == 0) then
                    nv = size(view%node) + 1
                    view%node = [view%node, ends(i)]
                    view%pair = [view%pair, ip]
                    view%group = [view%group, model%mesh%group(element)]
                    view%status = [view%status, contact_open]
                    view%placed = [view%placed, .false.]
                    view%p = [view%p, 0.0_dp]
                    view%q = [view%q, 0.0_dp]
                    view%gap = [view%gap, 0.0_dp]
                    view%slip = [view%slip, 0.0_dp]
                    index_of(ends(i)) = nv
                end if
                idx(i) = index_of(ends(i))
            end do
            view%seg = reshape([view%seg, idx], [2, size(view%seg, 2) + 1])
            view%seg_element = [view%seg_element, element]
        end subroutine add_face

        !> Reported node j of a swapped pair from the nearest active slave face; a node that
        !> overhangs the slave surface by half its faces or more (its tributary beyond that
        !> face's end: the rule of an unsupported slave node) is open and carries nothing.
        subroutine evaluate(j, faces)
            integer, intent(in) :: j, faces(:, :)
            real(dp) :: xi, best, dist, xi_best, n(2), xi_free, length
            integer :: f, a, b, near
            best = huge(1.0_dp)
            near = 0
            xi_best = 0.0_dp
            xi_free = 0.0_dp
            do f = 1, size(faces, 2)
                call closest_on_face(x(:, view%node(j)), x(:, contact%node(faces(1, f))), &
                                     x(:, contact%node(faces(2, f))), xi, dist)
                if (dist < best) then
                    best = dist
                    near = f
                    xi_free = xi
                    xi_best = min(1.0_dp, max(0.0_dp, xi))
                end if
            end do
            if (near == 0) return
            a = faces(1, near)
            b = faces(2, near)
            xi = xi_best
            n = face_normal(x(:, contact%node(a)), x(:, contact%node(b)))
            view%gap(j) = dot_product(x(:, view%node(j)) - x(:, contact%node(a)), n) - &
                          ((1.0_dp - xi)*contact%g0(a) + xi*contact%g0(b))
            if (contact%status(a) == contact_open .and. contact%status(b) == contact_open) then
                view%status(j) = contact_open
            else if (contact%status(a) /= contact_open .and. &
                     contact%status(b) /= contact_open) then
                view%status(j) = contact%status(merge(a, b, xi < 0.5_dp))
            else if (view%gap(j) > open_limit) then
                view%status(j) = contact_open
            else
                view%status(j) = contact%status(merge(a, b, contact%status(a) /= contact_open))
            end if
            length = norm2(x(:, contact%node(b)) - x(:, contact%node(a)))
            if (max(-xi_free, xi_free - 1.0_dp)*length >= half(j)) view%status(j) = contact_open
            view%slip(j) = (1.0_dp - xi)*contact%slip(a) + xi*contact%slip(b)
            if (view%status(j) == contact_open) return
            view%p(j) = (1.0_dp - xi)*contact%p(a) + xi*contact%p(b)
            view%q(j) = (1.0_dp - xi)*contact%q(a) + xi*contact%q(b)
        end subroutine evaluate
    end function reported_contact
end module cfrd_contact_view
