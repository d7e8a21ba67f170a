!> The effects a deck asks for (the EFFECTS card of CONTROL, docs/cards.md), applied to the
!> model once it is read: an effect that is off leaves the model without what it would
!> need, so the analysis neither assembles, searches nor stores it.
!> - ROCKFILL LINEAR: each E-B material becomes linear elastic with its moduli at
!>   sigma3 = pa and stress level 0 (one factorisation per active set, no midpoint step);
!> - UNLOAD OFF: the E-B laws keep no past maximum, so they never unload with Kur;
!> - WATER OFF: no RESERVOIR faces: WATER stages only move the level;
!> - INTERFACE BONDED: the JOINT lines are not assembled; the slab-side node of each pair is
!>   merged into its cushion-side node (the bonded model of the same mesh);
!> - FRICTION OFF: the CONTACT pairs are frictionless;
!> - SLIP SMALL: the contact geometry is searched only when faces are placed (cfrd_contact);
!> - PHASES OFF: the slab is cast in one piece, at the FILL stage of its last phase.
module cfrd_effects
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, effects_t, law_duncan_eb, law_elastic, stage_fill, method_joint
    use cfrd_duncan_eb, only: eb_params_t, eb_linear_moduli
    use cfrd_strings, only: to_text
    implicit none
    private

    public :: apply_effects, effects_text
    !> Fields of the EFFECTS card, in card order (for messages).
    integer, parameter, public :: effect_rockfill = 1, effect_unload = 2, effect_water = 3, &
                                  effect_interface = 4, effect_friction = 5, &
                                  effect_slip = 6, effect_phases = 7

contains

    !> Apply model%effects. A request the model cannot meet leaves `message` non-empty and
    !> `field` the card field it concerns; a request with nothing to act on adds a warning.
    subroutine apply_effects(model, field, message)
        type(model_t), intent(inout) :: model
        integer, intent(out) :: field
        character(len=:), allocatable, intent(out) :: message
        field = 0
        message = ''
        if (.not. model%effects%nonlinear_rockfill) call linear_rockfill(model)
        if (.not. model%effects%unload) call no_unloading(model)
        if (.not. model%effects%water) call no_water(model)
        if (.not. model%effects%interface) then
            call bond_joints(model, message)
            if (len(message) > 0) then
                field = effect_interface
                return
            end if
        end if
        if (.not. model%effects%friction) call no_friction(model)
        if (.not. model%effects%creep) call no_creep(model)
        if (.not. model%effects%large_slip .and. .not. has_contact(model)) &
            call warn(model, 'SLIP SMALL has no effect: the deck has no CONTACT pairs')
        if (.not. model%effects%phases) then
            call single_phase(model, message)
            if (len(message) > 0) field = effect_phases
        end if
    end subroutine apply_effects

    subroutine linear_rockfill(model)
        type(model_t), intent(inout) :: model
        integer :: m, n
        n = 0
        do m = 1, size(model%materials)
            associate (mat => model%materials(m))
                if (mat%law /= law_duncan_eb) cycle
                call eb_linear_moduli(eb_params_t(k=mat%k_modulus, n=mat%n_exponent, &
                                                  kb=mat%k_bulk, m=mat%m_exponent, &
                                                  pa=model%pa, &
                                                  sigma3_floor=mat%sigma3_floor), &
                                      mat%youngs_modulus, mat%poisson_ratio)
                mat%law = law_elastic
                n = n + 1
            end associate
        end do
        if (n == 0) call warn(model, 'ROCKFILL LINEAR has no effect: the deck has no EB '// &
                              'material')
    end subroutine linear_rockfill

    !> CREEP OFF: the CREEP cards are read and checked, and ignored.
    subroutine no_creep(model)
        type(model_t), intent(inout) :: model
        integer :: m
        if (.not. any(model%materials%creep)) &
            call warn(model, 'CREEP OFF has no effect: the deck has no CREEP card')
        do m = 1, size(model%materials)
            model%materials(m)%creep = .false.
        end do
    end subroutine no_creep

    subroutine no_unloading(model)
        type(model_t), intent(inout) :: model
        integer :: m
        do m = 1, size(model%materials)
            model%materials(m)%unload = .false.
        end do
        if (.not. any(model%materials%law == law_duncan_eb)) &
            call warn(model, 'UNLOAD OFF has no effect: the deck has no EB material (or '// &
                      'ROCKFILL is LINEAR)')
    end subroutine no_unloading

    subroutine no_water(model)
        type(model_t), intent(inout) :: model
        if (size(model%wet_faces) == 0) then
            call warn(model, 'WATER OFF has no effect: the deck has no RESERVOIR faces')
            return
        end if
        deallocate (model%wet_faces)
        allocate (model%wet_faces(0))
    end subroutine no_water

    subroutine no_friction(model)
        type(model_t), intent(inout) :: model
        if (.not. has_contact(model)) then
            call warn(model, 'FRICTION OFF has no effect: the deck has no CONTACT pairs '// &
                      '(the Goodman joints keep their shear law)')
            return
        end if
        model%contact_pairs%friction = 0.0_dp
    end subroutine no_friction

    !> The JOINT lines' slab-side nodes merged into their cushion-side nodes, the joint
    !> elements (the last ones of the mesh) dropped; the slab-side nodes are then used by no
    !> element and carry no equation.
    subroutine bond_joints(model, message)
        type(model_t), intent(inout) :: model
        character(len=:), allocatable, intent(inout) :: message
        integer, allocatable :: into(:)
        integer :: i, e, first, k, t, b, nkeep
        if (has_contact(model)) then
            message = 'INTERFACE BONDED needs node pairs to merge: the CONTACT bodies '// &
                      'share no node (run the bonded deck of the same mesh)'
            return
        end if
        if (size(model%interfaces) == 0) then
            call warn(model, 'INTERFACE BONDED has no effect: the deck has no INTERFACE '// &
                      'lines (its slab is bonded already)')
            return
        end if
        if (any(model%interfaces%method /= method_joint)) then
            message = 'INTERFACE BONDED merges coincident node pairs: the deck has THIN '// &
                      'layers, whose pairs lie a layer thickness apart'
            return
        end if
        first = minval(model%interfaces%element)
        nkeep = first - 1
        associate (mesh => model%mesh)
            allocate (into(mesh%nnode))
            into = [(i, i=1, mesh%nnode)]
            do i = 1, size(model%interfaces)
                e = model%interfaces(i)%element
                ! conn = (bottom k, bottom k+1, top k+1, top k)
                into(mesh%conn(4, e)) = mesh%conn(1, e)
                into(mesh%conn(3, e)) = mesh%conn(2, e)
            end do
            if (any(model%wet_faces%element > nkeep)) then
                message = 'INTERFACE BONDED drops the joints, and RESERVOIR faces lie on them'
                return
            end if
            do i = 1, size(model%load_sets)
                if (any(model%load_sets(i)%pressures%element > nkeep)) then
                    message = 'INTERFACE BONDED drops the joints, and PRESSURE loads act on them'
                    return
                end if
            end do
            mesh%nelem = nkeep
            mesh%conn = mesh%conn(:, 1:nkeep)
            mesh%kind = mesh%kind(1:nkeep)
            mesh%material = mesh%material(1:nkeep)
            mesh%group = mesh%group(1:nkeep)
            mesh%conn = reshape(into(pack(mesh%conn, .true.)), shape(mesh%conn))
            do t = 1, mesh%nnode
                b = into(t)
                if (b == t) cycle
                do k = 1, 2
                    if (model%fixed(k, t) .and. .not. model%fixed(k, b)) then
                        model%fixed(k, b) = .true.
                        model%prescribed(k, b) = model%prescribed(k, t)
                    end if
                end do
                model%fixed(:, t) = .false.
                model%prescribed(:, t) = 0.0_dp
                do i = 1, size(model%load_sets)
                    associate (f => model%load_sets(i)%nodal_force)
                        f(:, b) = f(:, b) + f(:, t)
                        f(:, t) = 0.0_dp
                    end associate
                end do
            end do
            do i = 1, size(model%gauges)
                model%gauges(i)%node = into(model%gauges(i)%node)
            end do
        end associate
        deallocate (model%interfaces)
        allocate (model%interfaces(0))
    end subroutine bond_joints

    !> The FILL stages of the SLAB groups but the last one dropped, their elements placed
    !> with the last one's group (and the faces they would cover wet until then).
    subroutine single_phase(model, message)
        type(model_t), intent(inout) :: model
        character(len=:), allocatable, intent(inout) :: message
        logical, allocatable :: keep(:), merged(:)
        integer :: s, last, g_last, i
        if (size(model%slab_groups) == 0) then
            message = 'PHASES OFF needs the SLAB cards that name the slab''s element groups'
            return
        end if
        last = 0
        do s = 1, size(model%stages)
            if (is_slab_fill(s)) last = s
        end do
        if (last == 0) then
            call warn(model, 'PHASES OFF has no effect: no FILL stage places a SLAB group')
            return
        end if
        g_last = model%stages(last)%group
        allocate (keep(size(model%stages)), source=.true.)
        allocate (merged(0:size(model%mesh%group_name)), source=.false.)
        do s = 1, last - 1
            if (.not. is_slab_fill(s)) cycle
            keep(s) = .false.
            merged(model%stages(s)%group) = .true.
        end do
        if (all(keep)) then
            call warn(model, 'PHASES OFF has no effect: the slab is cast in one phase')
            return
        end if
        where (merged(model%mesh%group)) model%mesh%group = g_last
        where (merged(model%wet_faces%cover)) model%wet_faces%cover = g_last
        do i = 1, size(model%load_sets)
            associate (gravity => model%load_sets(i)%gravity)
                where (merged(gravity%group)) gravity%group = g_last
            end associate
        end do
        model%stages = pack(model%stages, keep)
        model%slab_groups = [g_last]
    contains
        logical function is_slab_fill(s)
            integer, intent(in) :: s
            is_slab_fill = model%stages(s)%kind == stage_fill .and. &
                           any(model%slab_groups == model%stages(s)%group)
        end function is_slab_fill
    end subroutine single_phase

    !> The effects as the EFFECTS card words: 'ROCKFILL NONLINEAR, UNLOAD ON, ...'.
    pure function effects_text(effects) result(text)
        type(effects_t), intent(in) :: effects
        character(len=:), allocatable :: text
        text = 'ROCKFILL '//word(effects%nonlinear_rockfill, 'NONLINEAR', 'LINEAR')// &
               ', UNLOAD '//word(effects%unload, 'ON', 'OFF')// &
               ', WATER '//word(effects%water, 'ON', 'OFF')// &
               ', INTERFACE '//word(effects%interface, 'DECK', 'BONDED')// &
               ', FRICTION '//word(effects%friction, 'ON', 'OFF')// &
               ', SLIP '//word(effects%large_slip, 'LARGE', 'SMALL')// &
               ', PHASES '//word(effects%phases, 'ON', 'OFF')// &
               ', CREEP '//word(effects%creep, 'ON', 'OFF')
    contains
        pure function word(on, on_word, off_word) result(w)
            logical, intent(in) :: on
            character(len=*), intent(in) :: on_word, off_word
            character(len=:), allocatable :: w
            if (on) then
                w = on_word
            else
                w = off_word
            end if
        end function word
    end function effects_text

    logical function has_contact(model)
        type(model_t), intent(in) :: model
        has_contact = .false.
        if (allocated(model%contact_pairs)) has_contact = size(model%contact_pairs) > 0
    end function has_contact

    subroutine warn(model, text)
        type(model_t), intent(inout) :: model
        character(len=*), intent(in) :: text
        character(len=300) :: line
        line = 'EFFECTS card (line '//to_text(model%effects%line)//'): '//text
        model%warnings = [character(len=300) :: model%warnings, line]
    end subroutine warn
end module cfrd_effects
