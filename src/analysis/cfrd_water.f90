!> The reservoir: hydrostatic pressure gamma_w (level - y) on the wetted element faces of
!> the RESERVOIR group, below the current level (docs/theory.md section 11).
module cfrd_water
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, dry_level
    use cfrd_assembly, only: element_box_t
    implicit none
    private

    public :: water_forces, lowest_wet_point

contains

    !> Nodal forces (2, nnode) of the reservoir at `level` on every RESERVOIR face whose
    !> element is active and whose cover group (if any) has no active element yet. The
    !> pressure is linear on the wet part of a face and zero above the level; the face is
    !> cut at the waterline and the consistent forces of the wet part are carried to the
    !> face's nodes through the face's linear shape functions, which is exact (the parent
    !> shape functions are linear on the wet part).
    subroutine water_forces(model, library, active, level, force)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        real(dp), intent(in) :: level
        real(dp), intent(out) :: force(:, :)
        logical, allocatable :: placed(:)
        real(dp) :: xa(2), xb(2), s0, s1, p0, p1, f0(2), f1(2)
        integer :: i, e, a, b
        force = 0.0_dp
        if (level == dry_level .or. .not. allocated(model%wet_faces)) return
        associate (mesh => model%mesh)
            ! placed(g): some element of group g is active.
            allocate (placed(0:size(mesh%group_name)), source=.false.)
            do e = 1, mesh%nelem
                if (active(e)) placed(mesh%group(e)) = .true.
            end do
            do i = 1, size(model%wet_faces)
                associate (wet => model%wet_faces(i))
                    e = wet%element
                    if (.not. active(e)) cycle
                    if (wet%cover > 0) then
                        if (placed(wet%cover)) cycle
                    end if
                    a = mesh%conn(wet%face, e)
                    b = mesh%conn(mod(wet%face, 4) + 1, e)
                    xa = mesh%x(:, a)
                    xb = mesh%x(:, b)
                    call wet_interval(xa(2), xb(2), level, s0, s1)
                    if (.not. s1 > s0) cycle
                    p0 = model%gamma_w*(level - (xa(2) + s0*(xb(2) - xa(2))))
                    p1 = model%gamma_w*(level - (xa(2) + s1*(xb(2) - xa(2))))
                    call library(mesh%kind(e))%element%face_pressure( &
                        xa + s0*(xb - xa), xa + s1*(xb - xa), max(p0, 0.0_dp), &
                        max(p1, 0.0_dp), f0, f1)
                    force(:, a) = force(:, a) + (1.0_dp - s0)*f0 + (1.0_dp - s1)*f1
                    force(:, b) = force(:, b) + s0*f0 + s1*f1
                end associate
            end do
        end associate
    end subroutine water_forces

    !> The part [s0, s1] of the face xa -> xb (s from 0 to 1) that lies below the level;
    !> s1 <= s0 when the face is dry.
    pure subroutine wet_interval(ya, yb, level, s0, s1)
        real(dp), intent(in) :: ya, yb, level
        real(dp), intent(out) :: s0, s1
        real(dp) :: cut
        if (ya >= level .and. yb >= level) then
            s0 = 0.0_dp
            s1 = 0.0_dp
        else if (ya <= level .and. yb <= level) then
            s0 = 0.0_dp
            s1 = 1.0_dp
        else
            cut = (level - ya)/(yb - ya)
            if (ya < level) then
                s0 = 0.0_dp
                s1 = cut
            else
                s0 = cut
                s1 = 1.0_dp
            end if
        end if
    end subroutine wet_interval

    !> The lowest point of the RESERVOIR faces: where a first WATER stage starts to fill.
    pure real(dp) function lowest_wet_point(model) result(y)
        type(model_t), intent(in) :: model
        integer :: i
        y = huge(1.0_dp)
        do i = 1, size(model%wet_faces)
            associate (wet => model%wet_faces(i), mesh => model%mesh)
                y = min(y, mesh%x(2, mesh%conn(wet%face, wet%element)), &
                        mesh%x(2, mesh%conn(mod(wet%face, 4) + 1, wet%element)))
            end associate
        end do
    end function lowest_wet_point
end module cfrd_water
