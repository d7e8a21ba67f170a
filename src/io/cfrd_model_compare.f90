!> Whether two decks describe the same analysis up to a stage (cfrd --restart DECK): the
!> mesh, materials, supports, load sets, reservoir faces, interfaces, slab groups, contact
!> pairs, effects and control values, and stages 1 .. K themselves. The first difference is
!> described in words (what, and the two values); gauges and titles may differ (they
!> change what is printed, not what is computed).
module cfrd_model_compare
    use cfrd_kinds, only: dp
    use cfrd_strings, only: to_text
    use cfrd_model, only: model_t, material_t, stage_kind_name
    implicit none
    private

    public :: first_difference

    !> The first difference found ('' while none).
    type :: finder_t
        character(len=:), allocatable :: text
    end type finder_t

contains

    !> '' when `new` is `old` up to stage `upto`, else the first difference: what differs,
    !> its value in `new`, then in `old`.
    function first_difference(old, new, upto) result(text)
        type(model_t), intent(in) :: old, new
        integer, intent(in) :: upto
        character(len=:), allocatable :: text
        type(finder_t) :: f
        integer :: i
        f%text = ''
        call same_int(f, 'the analysis type (CONTROL)', old%analysis, new%analysis)
        call same_reals(f, 'pa (CONTROL)', [old%pa], [new%pa])
        call same_reals(f, 'the unit weight of water (CONTROL)', [old%gamma_w], [new%gamma_w])
        call same_int(f, 'NEWTOP (CONTROL)', old%newtop, new%newtop)
        call same_int(f, 'SOLVER (CONTROL)', old%solver, new%solver)
        call same_reals(f, 'the Newton tolerance (CONTROL)', [old%tolerance], [new%tolerance])
        call same_int(f, 'the Newton iterations (CONTROL)', old%max_iterations, new%max_iterations)
        call same_reals(f, 'the error tolerance (CONTROL ERRCTL)', [old%error_tolerance], &
                        [new%error_tolerance])
        call same_int(f, 'the error control depth (CONTROL ERRCTL)', old%max_depth, &
                      new%max_depth)
        associate (a => old%effects, b => new%effects)
            call same_flags(f, 'the EFFECTS card', [a%nonlinear_rockfill, a%unload, a%water, &
                       a%interface, a%friction, a%large_slip, a%phases, a%creep], &
                       [b%nonlinear_rockfill, b%unload, b%water, b%interface, b%friction, &
                        b%large_slip, b%phases, b%creep])
        end associate
        call mesh(f, old, new)
        call materials(f, old, new)
        call same_flags(f, 'the supports (BOUNDARY)', pack(old%fixed, .true.), &
                        pack(new%fixed, .true.))
        call same_reals(f, 'the prescribed displacements (BOUNDARY)', &
                        pack(old%prescribed, .true.), pack(new%prescribed, .true.))
        call loads(f, old, new)
        call surfaces(f, old, new)
        call same_int(f, 'the number of stages up to '//to_text(upto), &
                      min(upto, size(old%stages)), &
                 min(upto, size(new%stages)))
        do i = 1, min(upto, size(old%stages), size(new%stages))
            call stage(f, i, old, new)
        end do
        text = f%text
    end function first_difference

    subroutine mesh(f, old, new)
        type(finder_t), intent(inout) :: f
        type(model_t), intent(in) :: old, new
        associate (a => old%mesh, b => new%mesh)
            call same_int(f, 'the number of nodes', a%nnode, b%nnode)
            call same_int(f, 'the number of elements', a%nelem, b%nelem)
            if (len(f%text) > 0) return
            call same_reals(f, 'the node coordinates', pack(a%x, .true.), pack(b%x, .true.))
            call same_ints(f, 'the element nodes', pack(a%conn, .true.), pack(b%conn, .true.))
            call same_ints(f, 'the element types', a%kind, b%kind)
            call same_ints(f, 'the element materials', a%material, b%material)
            call same_ints(f, 'the element groups', a%group, b%group)
            call same_int(f, 'the number of element groups', size(a%group_name), size(b%group_name))
            if (len(f%text) > 0) return
            if (any(a%group_name /= b%group_name)) call found(f, 'the element group names')
        end associate
    end subroutine mesh

    subroutine materials(f, old, new)
        type(finder_t), intent(inout) :: f
        type(model_t), intent(in) :: old, new
        integer :: m
        call same_int(f, 'the number of materials', size(old%materials), size(new%materials))
        do m = 1, min(size(old%materials), size(new%materials))
            associate (a => old%materials(m), b => new%materials(m))
                call same_int(f, 'material '//to_text(m)//': the law', a%law, b%law)
                call same_reals(f, 'material '//to_text(m)//' ('//b%label//'): a parameter', &
                          values(a), values(b))
                call same_flags(f, 'material '//to_text(m)//' ('//b%label//'): a switch', &
                           [a%tension_cutoff, a%unload, a%creep, a%wetting], &
                           [b%tension_cutoff, b%unload, b%creep, b%wetting])
            end associate
        end do
    contains
        pure function values(p) result(v)
            type(material_t), intent(in) :: p
            real(dp), allocatable :: v(:)
            v = [p%unit_weight, p%youngs_modulus, p%poisson_ratio, p%k_modulus, &
                 p%n_exponent, p%failure_ratio, p%k_bulk, p%m_exponent, p%phi0, p%dphi, &
                 p%cohesion, p%k_unload, p%sigma3_floor, p%kn_compression, p%kn_tension, &
                 p%k1, p%n1, p%rf1, p%phi, p%sigma_n_floor, p%gamma_w, p%creep_alpha, &
                 p%creep_b, p%creep_mc, p%creep_d, p%creep_l, p%wet_c, p%wet_n, p%wet_d, &
                 p%tensile_strength, p%ks_joint]
        end function values
    end subroutine materials

    subroutine loads(f, old, new)
        type(finder_t), intent(inout) :: f
        type(model_t), intent(in) :: old, new
        integer :: i, k
        call same_int(f, 'the number of load sets', size(old%load_sets), size(new%load_sets))
        do i = 1, min(size(old%load_sets), size(new%load_sets))
            associate (a => old%load_sets(i), b => new%load_sets(i))
                if (a%name /= b%name) call found(f, 'the name of load set '//to_text(i))
                call same_reals(f, 'the nodal forces of load set '//to_text(i), &
                          pack(a%nodal_force, .true.), pack(b%nodal_force, .true.))
                call same_int(f, 'the gravity loads of load set '//to_text(i), size(a%gravity), &
                         size(b%gravity))
                call same_int(f, 'the pressures of load set '//to_text(i), size(a%pressures), &
                         size(b%pressures))
                if (len(f%text) > 0) return
                do k = 1, size(a%gravity)
                    call same_int(f, 'a gravity group of load set '//to_text(i), &
                                  a%gravity(k)%group, b%gravity(k)%group)
                    call same_reals(f, 'a gravity load of load set '//to_text(i), &
                                    [a%gravity(k)%ax, a%gravity(k)%ay], &
                                    [b%gravity(k)%ax, b%gravity(k)%ay])
                end do
                call same_ints(f, 'the pressure faces of load set '//to_text(i), &
                          [a%pressures%element, a%pressures%face], &
                          [b%pressures%element, b%pressures%face])
                call same_reals(f, 'the pressures of load set '//to_text(i), &
                          [a%pressures%p1, a%pressures%p2], [b%pressures%p1, b%pressures%p2])
            end associate
        end do
    end subroutine loads

    !> Reservoir faces, interfaces, slab groups and contact.
    subroutine surfaces(f, old, new)
        type(finder_t), intent(inout) :: f
        type(model_t), intent(in) :: old, new
        integer :: i
        if (allocated(old%wet_faces) .and. allocated(new%wet_faces)) then
            call same_int(f, 'the number of RESERVOIR faces', size(old%wet_faces), &
                          size(new%wet_faces))
            if (len(f%text) == 0) call same_ints(f, 'the RESERVOIR faces', &
                [old%wet_faces%element, old%wet_faces%face, old%wet_faces%cover], &
                [new%wet_faces%element, new%wet_faces%face, new%wet_faces%cover])
        else if (allocated(old%wet_faces) .neqv. allocated(new%wet_faces)) then
            call found(f, 'the RESERVOIR cards')
        end if
        if (allocated(old%interfaces) .and. allocated(new%interfaces)) then
            call same_ints(f, 'the INTERFACE elements', [old%interfaces%element, &
                      old%interfaces%line, old%interfaces%method], [new%interfaces%element, &
                      new%interfaces%line, new%interfaces%method])
        else if (allocated(old%interfaces) .neqv. allocated(new%interfaces)) then
            call found(f, 'the INTERFACE cards')
        end if
        if (allocated(old%slab_groups) .and. allocated(new%slab_groups)) then
            call same_ints(f, 'the SLAB groups', old%slab_groups, new%slab_groups)
        else if (allocated(old%slab_groups) .neqv. allocated(new%slab_groups)) then
            call found(f, 'the SLAB cards')
        end if
        if (allocated(old%plinth_groups) .and. allocated(new%plinth_groups)) then
            call same_ints(f, 'the PLINTH groups', old%plinth_groups, new%plinth_groups)
        else if (allocated(old%plinth_groups) .neqv. allocated(new%plinth_groups)) then
            call found(f, 'the PLINTH cards')
        end if
        if (allocated(old%contact_pairs) .neqv. allocated(new%contact_pairs)) then
            call found(f, 'the CONTACT cards')
            return
        end if
        if (.not. allocated(old%contact_pairs)) return
        call same_int(f, 'the number of CONTACT pairs', size(old%contact_pairs), &
                 size(new%contact_pairs))
        call same_int(f, 'the number of CONTACT surfaces', size(old%surfaces), size(new%surfaces))
        if (len(f%text) > 0) return
        do i = 1, size(old%surfaces)
            call same_ints(f, 'CONTACT surface '//trim(new%surfaces(i)%name), &
                      [old%surfaces(i)%element, old%surfaces(i)%face], &
                      [new%surfaces(i)%element, new%surfaces(i)%face])
        end do
        do i = 1, size(old%contact_pairs)
            associate (a => old%contact_pairs(i), b => new%contact_pairs(i))
                call same_ints(f, 'CONTACT pair '//to_text(i)//' (line '//to_text(b%line)//')', &
                          [a%slave, a%master, a%scheme, a%search], &
                          [b%slave, b%master, b%scheme, b%search])
                call same_reals(f, 'CONTACT pair '//to_text(i)//' (line '//to_text(b%line)// &
                          '): friction or tolerance', [a%friction, a%tolerance], &
                          [b%friction, b%tolerance])
                call same_flags(f, 'CONTACT pair '//to_text(i)//' (line '//to_text(b%line)// &
                           '): CAST or the roles', [a%cast, a%swapped], [b%cast, b%swapped])
            end associate
        end do
    end subroutine surfaces

    subroutine stage(f, i, old, new)
        type(finder_t), intent(inout) :: f
        integer, intent(in) :: i
        type(model_t), intent(in) :: old, new
        character(len=:), allocatable :: what
        associate (a => old%stages(i), b => new%stages(i))
            what = 'stage '//to_text(i)//' (line '//to_text(b%line)//', '//trim(b%label)//')'
            if (a%kind /= b%kind) call found(f, what//': '//stage_kind_name(b%kind)// &
                                             ' here, '//stage_kind_name(a%kind)//' there')
            call same_int(f, what//': the group', a%group, b%group)
            call same_int(f, what//': the load set', a%load_set, b%load_set)
            call same_reals(f, what//': the level', [a%level], [b%level])
            call same_int(f, what//': the increments', a%increments, b%increments)
            call same_reals(f, what//': the date', [a%day], [b%day])
            if (a%label /= b%label) call found(f, what//': the label')
        end associate
    end subroutine stage

    subroutine found(f, text)
        type(finder_t), intent(inout) :: f
        character(len=*), intent(in) :: text
        if (len(f%text) == 0) f%text = text
    end subroutine found

    subroutine same_int(f, what, a, b)
        type(finder_t), intent(inout) :: f
        character(len=*), intent(in) :: what
        integer, intent(in) :: a, b
        if (a /= b) call found(f, what//': '//to_text(b)//' here, '//to_text(a)//' there')
    end subroutine same_int

    !> Integers compare as reals (exact below 2**53).
    subroutine same_ints(f, what, a, b)
        type(finder_t), intent(inout) :: f
        character(len=*), intent(in) :: what
        integer, intent(in) :: a(:), b(:)
        call same_reals(f, what, real(a, dp), real(b, dp))
    end subroutine same_ints

    !> Reals compare bit for bit (both decks are read by the same reader).
    subroutine same_reals(f, what, a, b)
        type(finder_t), intent(inout) :: f
        character(len=*), intent(in) :: what
        real(dp), intent(in) :: a(:), b(:)
        integer :: k
        if (size(a) /= size(b)) then
            call found(f, what//': '//to_text(size(b))//' values here, '// &
                       to_text(size(a))//' there')
            return
        end if
        do k = 1, size(a)
            if (a(k) /= b(k)) then
                if (size(a) == 1) then
                    call found(f, what//': '//number(b(k))//' here, '//number(a(k))//' there')
                else
                    call found(f, what//', value '//to_text(k)//': '//number(b(k))// &
                               ' here, '//number(a(k))//' there')
                end if
                return
            end if
        end do
    end subroutine same_reals

    !> A value as text: an integer without decimals, else 10 significant digits.
    function number(x) result(text)
        real(dp), intent(in) :: x
        character(len=:), allocatable :: text
        character(len=32) :: buffer
        if (x == aint(x) .and. abs(x) < 1.0e15_dp) then
            write (buffer, '(i0)') nint(x, kind=8)
        else
            write (buffer, '(g0.10)') x
        end if
        text = trim(buffer)
    end function number

    subroutine same_flags(f, what, a, b)
        type(finder_t), intent(inout) :: f
        character(len=*), intent(in) :: what
        logical, intent(in) :: a(:), b(:)
        if (size(a) /= size(b)) then
            call found(f, what)
        else if (any(a .neqv. b)) then
            call found(f, what//' differs')
        end if
    end subroutine same_flags
end module cfrd_model_compare
