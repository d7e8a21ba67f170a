!> Checks of a model that need no card positions: element geometry, nodes used by no
!> element, and rigid-body modes that the prescribed dofs leave free (docs/theory.md,
!> sections 3 and 5). They return what is wrong; the deck reader words the message.
module cfrd_model_check
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, mesh_t, stage_fill, stage_load, fill_active
    implicit none
    private

    public :: element_shape, first_unused_node, free_rigid_mode, unplaced_load
    public :: layer_thickness
    public :: shape_ok, shape_degenerate, shape_inverted

    integer, parameter :: shape_ok = 0, shape_degenerate = 1, shape_inverted = 2

contains

    !> Sign of det J over element e: det J of a bilinear quad is linear in (xi, eta), so it is
    !> positive everywhere when the edge cross product at each corner is. A triangle (node 4 =
    !> node 3) has one zero corner by construction; its area decides.
    pure integer function element_shape(mesh, e) result(status)
        type(mesh_t), intent(in) :: mesh
        integer, intent(in) :: e
        real(dp) :: p(2, 4), cross, tol, size2
        integer :: k, prev, next
        p = mesh%x(:, mesh%conn(:, e))
        size2 = 0.0_dp
        do k = 1, 4
            size2 = max(size2, sum((p(:, mod(k, 4) + 1) - p(:, k))**2))
        end do
        tol = 1.0e-10_dp*size2
        status = shape_ok
        if (mesh%conn(4, e) == mesh%conn(3, e)) then
            cross = cross2(p(:, 2) - p(:, 1), p(:, 3) - p(:, 1))
            if (cross < -tol) then
                status = shape_inverted
            else if (cross <= tol) then
                status = shape_degenerate
            end if
            return
        end if
        do k = 1, 4
            next = mod(k, 4) + 1
            prev = mod(k + 2, 4) + 1
            cross = cross2(p(:, next) - p(:, k), p(:, prev) - p(:, k))
            if (cross < -tol) then
                status = shape_inverted
                return
            else if (cross <= tol) then
                status = shape_degenerate
            end if
        end do
    end function element_shape

    !> Thickness of a thin-layer quad p(2,4) (faces 1-2 and 3-4 along the layer): its area
    !> over the mean length of those faces.
    pure real(dp) function layer_thickness(p) result(thick)
        real(dp), intent(in) :: p(2, 4)
        real(dp) :: area
        area = 0.5_dp*((p(1, 3) - p(1, 1))*(p(2, 4) - p(2, 2)) - &
                       (p(1, 4) - p(1, 2))*(p(2, 3) - p(2, 1)))
        thick = area/(0.5_dp*(norm2(p(:, 2) - p(:, 1)) + norm2(p(:, 3) - p(:, 4))))
    end function layer_thickness

    pure real(dp) function cross2(a, b)
        real(dp), intent(in) :: a(2), b(2)
        cross2 = a(1)*b(2) - a(2)*b(1)
    end function cross2

    !> The first node that no element uses, or 0.
    pure integer function first_unused_node(mesh) result(node)
        type(mesh_t), intent(in) :: mesh
        logical, allocatable :: used(:)
        integer :: e
        allocate (used(mesh%nnode), source=.false.)
        do e = 1, mesh%nelem
            used(mesh%conn(:, e)) = .true.
        end do
        node = findloc(used, .false., dim=1)
    end function first_unused_node

    !> Which rigid-body mode of the plane the prescribed dofs leave free: '' when none,
    !> else 'translation in x', 'translation in y' or 'rotation'. The rows (1, 0, -y) of x dofs
    !> and (0, 1, x) of y dofs (coordinates centred and scaled) must have rank 3.
    pure function free_rigid_mode(model) result(mode)
        type(model_t), intent(in) :: model
        character(len=:), allocatable :: mode
        real(dp) :: centre(2), scale, g(3, 3), row(3), c(2), det
        integer :: node
        mode = ''
        if (.not. any(model%fixed(1, :))) then
            mode = 'translation in x'
            return
        end if
        if (.not. any(model%fixed(2, :))) then
            mode = 'translation in y'
            return
        end if
        centre = sum(model%mesh%x, dim=2)/model%mesh%nnode
        scale = max(maxval(abs(model%mesh%x(1, :) - centre(1))), &
                    maxval(abs(model%mesh%x(2, :) - centre(2))), tiny(1.0_dp))
        g = 0.0_dp
        do node = 1, model%mesh%nnode
            c = (model%mesh%x(:, node) - centre)/scale
            if (model%fixed(1, node)) then
                row = [1.0_dp, 0.0_dp, -c(2)]
                g = g + spread(row, 2, 3)*spread(row, 1, 3)
            end if
            if (model%fixed(2, node)) then
                row = [0.0_dp, 1.0_dp, c(1)]
                g = g + spread(row, 2, 3)*spread(row, 1, 3)
            end if
        end do
        det = g(1, 1)*(g(2, 2)*g(3, 3) - g(2, 3)*g(3, 2)) &
              - g(1, 2)*(g(2, 1)*g(3, 3) - g(2, 3)*g(3, 1)) &
              + g(1, 3)*(g(2, 1)*g(3, 2) - g(2, 2)*g(3, 1))
        if (det <= 1.0e-10_dp*g(1, 1)*g(2, 2)*max(g(3, 3), 1.0_dp)) mode = 'rotation'
    end function free_rigid_mode

    !> The first LOAD stage whose load set loads what is not placed yet: returns the stage
    !> and either the element of a PRESSURE (what = 1) or the node of a FORCE (what = 2);
    !> stage = 0 when every load falls on placed parts. Elements of groups that a FILL stage
    !> places are absent before it (as the stage driver does).
    pure subroutine unplaced_load(model, stage, what, item)
        type(model_t), intent(in) :: model
        integer, intent(out) :: stage, what, item
        logical, allocatable :: filled(:), active(:), used(:)
        integer :: s, k, e, node
        stage = 0
        what = 0
        item = 0
        allocate (filled(0:size(model%mesh%group_name)), source=.false.)
        do s = 1, size(model%stages)
            if (model%stages(s)%kind == stage_fill) filled(model%stages(s)%group) = .true.
        end do
        active = .not. filled(model%mesh%group)
        do s = 1, size(model%stages)
            associate (st => model%stages(s))
                if (st%kind == stage_fill) then
                    active = fill_active(model%mesh, active, st%group)
                else if (st%kind == stage_load) then
                    associate (loads => model%load_sets(st%load_set))
                        do k = 1, size(loads%pressures)
                            if (.not. active(loads%pressures(k)%element)) then
                                stage = s
                                what = 1
                                item = loads%pressures(k)%element
                                return
                            end if
                        end do
                        allocate (used(model%mesh%nnode), source=.false.)
                        do e = 1, model%mesh%nelem
                            if (active(e)) used(model%mesh%conn(:, e)) = .true.
                        end do
                        do node = 1, model%mesh%nnode
                            if (any(loads%nodal_force(:, node) /= 0.0_dp) .and. &
                                .not. used(node)) then
                                stage = s
                                what = 2
                                item = node
                                return
                            end if
                        end do
                        deallocate (used)
                    end associate
                end if
            end associate
        end do
    end subroutine unplaced_load
end module cfrd_model_check
