!> Cast in place with the roles swapped (docs/theory.md section 14, "Roles"): where a pair's
!> finer surface (the slab) was made its master (cfrd_contact_roles), the slave (the
!> cushion) is placed long before the master's faces, so CAST cannot count the slave's gap at
!> its own placement as closed. Instead each master node, at the search where it is first
!> active, is moved onto the slave surface along that surface's normal, and the move is kept
!> in the contact's displacement since placement (contact_t%u): the slab is cast against the
!> cushion as it is then, and its gaps count from there, as the slave-side g0 does when the
!> slab is the slave.
module cfrd_contact_cast
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t
    use cfrd_mortar, only: face_normal, closest_on_face
    implicit none
    private

    public :: cast_master_offsets

contains

    !> For the master nodes `born` at this search on an active master face of a swapped CAST
    !> pair: x and u move by -((x - x_a) . n_s) n_s, (x_a, n_s) the active slave face of the
    !> pair nearest to the node among those facing the master face, within two of that slave
    !> face's lengths (none: no move). Other nodes and pairs are not touched.
    pure subroutine cast_master_offsets(model, node, pair, seg, seg_on, mseg, mseg_pair, &
                                        mseg_on, born, x, u)
        type(model_t), intent(in) :: model
        integer, intent(in) :: node(:), pair(:)     !! (nc) slave nodes' mesh nodes, pairs
        integer, intent(in) :: seg(:, :)            !! (2, ns) slave faces (contact nodes)
        logical, intent(in) :: seg_on(:)
        integer, intent(in) :: mseg(:, :)           !! (2, nm) master faces (mesh nodes)
        integer, intent(in) :: mseg_pair(:)
        logical, intent(in) :: mseg_on(:)
        logical, intent(in) :: born(:)              !! (nnode) first active at this search
        real(dp), intent(inout) :: x(:, :), u(:, :) !! (2, nnode)
        logical, allocatable :: done(:)
        real(dp) :: n_m(2), offset(2), best, dist, xi
        integer :: km, j, k, ip, m
        allocate (done(size(born)), source=.false.)
        do km = 1, size(mseg, 2)
            if (.not. mseg_on(km)) cycle
            ip = mseg_pair(km)
            if (.not. (model%contact_pairs(ip)%swapped .and. model%contact_pairs(ip)%cast)) cycle
            n_m = face_normal(x(:, mseg(1, km)), x(:, mseg(2, km)))
            do j = 1, 2
                m = mseg(j, km)
                if (.not. born(m) .or. done(m)) cycle
                done(m) = .true.
                best = huge(1.0_dp)
                offset = 0.0_dp
                do k = 1, size(seg, 2)
                    if (.not. seg_on(k) .or. pair(seg(1, k)) /= ip) cycle
                    associate (xa => x(:, node(seg(1, k))), xb => x(:, node(seg(2, k))))
                        if (dot_product(face_normal(xa, xb), n_m) >= 0.0_dp) cycle
                        call closest_on_face(x(:, m), xa, xb, xi, dist)
                        if (dist > 2.0_dp*norm2(xb - xa) .or. dist >= best) cycle
                        best = dist
                        offset = -dot_product(x(:, m) - xa, face_normal(xa, xb))* &
                                 face_normal(xa, xb)
                    end associate
                end do
                x(:, m) = x(:, m) + offset
                u(:, m) = u(:, m) + offset
            end do
        end do
    end subroutine cast_master_offsets
end module cfrd_contact_cast
