!> The restart state of a stage in the results file (docs/results.md, "Restart", layout 4):
!> the group stages/stage_NNNN/state holds what the next stage needs beyond the stage's own
!> datasets (the carry: displacements before the last RESET, applied load, wetted elements,
!> contact state, multiplier scale), and in double precision the stage's own state fields
!> when the file stores them in single (--float32). read_stored_stage gives a stage back as
!> the stage driver needs it for a restart: those fields, the carry, and the stage's figures
!> (increments, factorisations, times, solver counts) as they were written.
module cfrd_h5_state
    use hdf5, only: hid_t, h5gopen_f, h5gclose_f, h5ocopy_f
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, io_error
    use cfrd_model, only: dry_level, no_date, stage_reset
    use cfrd_results, only: stage_result_t, carry_t
    use cfrd_h5_datasets, only: h5_state_t, fail, open_group, close_group, dataset_real1, &
                          dataset_real2, dataset_real3, dataset_int1, &
                          attr_real, attr_int, set_attr_int
    use cfrd_h5_read, only: int_attribute, real_attribute, has_object, read_reals, read_ints
    implicit none
    private

    public :: write_stage_state, read_stored_stage, copy_stage

    !> state/ints starts with nlengths lengths (state_lengths); state/reals holds, in order:
    character(len=*), parameter :: state_reals = 'f_ext (2, nnode); u_before_reset '// &
        '(2, nnode) at RESET stages; with contact, per slave node p, q, g0, gap, slip, w, '// &
        'wref, g, g_curve, normal (2, nc), tangent (2, nc), then cpl_a (ncpl), u (2, nnode)'
    integer, parameter :: nlengths = 8

contains

    !> The group `state` of the stage group `stage_id`: attributes, and the carry packed in
    !> two datasets, `reals` and `ints` (few HDF5 objects: each costs a run time), laid out
    !> as state_lengths says. `filtered` (a lean file): both through the filters like the
    !> stage's fields when large enough, else contiguous.
    subroutine write_stage_state(stage_id, stage, st, filtered)
        integer(hid_t), intent(in) :: stage_id
        type(stage_result_t), intent(in) :: stage
        type(h5_state_t), intent(inout) :: st
        logical, intent(in) :: filtered
        integer(hid_t) :: id
        integer :: n(nlengths), deflate
        logical :: single
        real(dp), allocatable :: reals(:), g_curve(:)
        integer, allocatable :: ints(:)
        single = st%single
        deflate = st%deflate
        ! the packed state unfiltered in a full file, as before issue 21's lean files (the
        ! deflate filter cost the x2 contact deck 4 %, docs/performance.md (j))
        st%single = .false.
        st%deflate = 0
        call open_group(stage_id, 'state', id, st)
        associate (c => stage%carry)
            call attr_int(id, 'prescribed_done', merge(1, 0, c%prescribed_done), st)
            call attr_real(id, 'contact_scale', [c%contact_scale], st)
            call attr_int(id, 'searches', c%searches, st)
            n = state_lengths(stage)
            reals = pack(c%f_ext, .true.)
            ! it changes at RESET stages only: a stage without it has the last one's
            if (n(7) == 1) reals = [reals, pack(c%u_before_reset, .true.)]
            ints = n
            if (n(8) == 1) ints = [ints, merge(1, 0, c%wetted)]
            if (n(3) >= 0) then
                allocate (g_curve(n(3)), source=0.0_dp)
                if (allocated(c%g_curve)) g_curve = c%g_curve
                reals = [reals, c%p, c%q, c%g0, c%gap, c%slip, c%w, c%wref, c%g, g_curve, &
                         pack(c%normal, .true.), pack(c%tangent, .true.), c%cpl_a, &
                         pack(c%u, .true.)]
                ints = [ints, merge(1, 0, c%placed), merge(1, 0, c%supported), c%status, &
                        c%slip_sign, c%birth, c%cpl_ptr, c%cpl_node]
                if (n(5) >= 0) ints = [ints, merge(1, 0, c%seg_searched), &
                                       merge(1, 0, c%mseg_searched)]
                ! the friction groups (cfrd_contact: friction_groups), after everything else
                ints = [ints, c%ngroup, c%tgroup, c%grp_ptr, c%grp_node]
                reals = [reals, c%beta]
            end if
            ! a lean file: the loads compress to about 0.3 (zeros of the nodes not yet
            ! placed, loads that repeat), the contact state's integers (stage numbers,
            ! flags) to little, for about 1 % of a run (docs/performance.md (q-files))
            if (filtered) st%deflate = deflate
            call dataset_real1(id, 'reals', reals, 'kN/m, m, kPa, m2, -', state_reals, st)
            call dataset_int1(id, 'ints', ints, st)
            st%deflate = 0
        end associate
        st%deflate = deflate
        if (single) then
            ! the fields the next stage starts from, to the bit (the stage's are single;
            ! filtered as they are: a --float32 run asked for a small file)
            call dataset_real2(id, 'displacement', stage%displacement, 'm', 'ux, uy', st)
            call dataset_real3(id, 'stress_gauss', stage%stress_gauss, 'kPa', &
                               'xx, yy, zz, xy', st)
            call dataset_real3(id, 'strain_gauss', stage%strain_gauss, '-, m', &
                               'xx, yy, zz, xy (joints: du_n, du_s)', st)
            call dataset_real3(id, 'history_gauss', stage%history_gauss, '-', 'SS, SL', st)
            if (allocated(stage%creep_gauss)) call dataset_real3(id, 'creep_gauss', &
                stage%creep_gauss, '-', 'volumetric, shear', st)
            if (allocated(stage%wetting_gauss)) call dataset_real3(id, 'wetting_gauss', &
                stage%wetting_gauss, '-', 'volumetric, shear', st)
        end if
        call close_group(id, st)
        st%single = single
        st%deflate = deflate
    end subroutine write_stage_state

    !> The lengths that lay `state/reals` and `state/ints` out (the first nlengths values of
    !> `ints`): nodes, elements, slave nodes (-1: no contact), couplings, slave and master
    !> segments searched (-1: none yet), whether u_before_reset and wetted are there.
    function state_lengths(stage) result(n)
        type(stage_result_t), intent(in) :: stage
        integer :: n(nlengths)
        associate (c => stage%carry)
            n = [size(c%f_ext, 2), size(stage%active), -1, 0, -1, -1, &
                 merge(1, 0, stage%kind == stage_reset), merge(1, 0, allocated(c%wetted))]
            if (allocated(c%p)) then
                n(3:4) = [size(c%p), size(c%cpl_a)]
                if (allocated(c%seg_searched)) n(5:6) = [size(c%seg_searched), &
                                                         size(c%mseg_searched)]
            end if
        end associate
    end function state_lengths

    !> Stage `number` copied as it is (HDF5's object copy: the chunks as stored, no filter
    !> run again) from the results file `source_id` into the file being written (its
    !> /stages group `stages_id`, root `file_id`, path `path`) and counted in
    !> `stages_completed`: what write_stage_h5 would write for the stage when both files
    !> store their values alike (a restart's stored stages). Not flushed: the next stage
    !> written flushes the copies with it (the stored stages are safe in their own file).
    subroutine copy_stage(source_id, file_id, stages_id, path, number, error)
        integer(hid_t), intent(in) :: source_id, file_id, stages_id
        character(len=*), intent(in) :: path
        integer, intent(in) :: number
        type(error_t), allocatable, intent(out) :: error
        type(h5_state_t) :: st
        character(len=10) :: name
        integer :: hdferr
        write (name, '(a,i4.4)') 'stage_', number
        call h5ocopy_f(source_id, 'stages/'//name, stages_id, name, hdferr)
        if (hdferr < 0) call fail(st, 'copying '//name)
        call set_attr_int(file_id, 'stages_completed', number, st)
        if (.not. st%ok) call fatal_error(error, 'cannot write the results file '//path// &
                                          ': HDF5 failed at '//st%failed, io_error)
    end subroutine copy_stage

    !> Stage `number` of the open results file `file_id` (path `path`, for messages).
    !> `light`: only what the stage's summary and CSV rows need (not the history, creep and
    !> wetting strains, nor the applied load).
    subroutine read_stored_stage(file_id, path, number, stage, error, light)
        integer(hid_t), intent(in) :: file_id
        character(len=*), intent(in) :: path
        integer, intent(in) :: number
        type(stage_result_t), intent(out) :: stage
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in) :: light
        type(h5_state_t) :: st
        integer(hid_t) :: stage_id, state_id, id
        integer :: hdferr
        integer, allocatable :: flags(:)
        character(len=24) :: name
        write (name, '(a,i4.4)') 'stages/stage_', number
        call h5gopen_f(file_id, trim(name), stage_id, hdferr)
        if (hdferr < 0) then
            call fatal_error(error, path//': no group '//trim(name), io_error)
            return
        end if
        stage%increments = int_attribute(stage_id, 'increments')
        stage%factorisations = int_attribute(stage_id, 'factorisations')
        stage%iterations = int_attribute(stage_id, 'iterations')
        stage%cutbacks = int_attribute(stage_id, 'cutbacks')
        stage%max_residual = real_attribute(stage_id, 'max_residual', 0.0_dp)
        stage%wall_time = real_attribute(stage_id, 'wall_time', 0.0_dp)
        stage%water_level = real_attribute(stage_id, 'water_level', dry_level)
        stage%day = real_attribute(stage_id, 'day', no_date)
        stage%near_failure = int_attribute(stage_id, 'near_failure')
        call read_stats(stage_id, stage, st)
        call read_ints(stage_id, 'active', flags, st)
        stage%active = flags == 1
        call h5gopen_f(stage_id, 'state', state_id, hdferr)
        if (hdferr < 0) then
            call fail(st, trim(name)//'/state')
        else
            ! the double copies of a --float32 file, else the stage's own datasets
            id = merge(state_id, stage_id, has_object(state_id, 'stress_gauss'))
            call read_reals(id, 'displacement', stage%displacement, st)
            call read_reals(id, 'stress_gauss', stage%stress_gauss, st)
            call read_reals(id, 'strain_gauss', stage%strain_gauss, st)
            if (.not. light) then
                call read_reals(id, 'history_gauss', stage%history_gauss, st)
                if (has_object(stage_id, 'creep_gauss')) &
                    call read_reals(id, 'creep_gauss', stage%creep_gauss, st)
                if (has_object(stage_id, 'wetting_gauss')) &
                    call read_reals(id, 'wetting_gauss', stage%wetting_gauss, st)
            end if
            call read_carry(state_id, stage%carry, st)
            call h5gclose_f(state_id, hdferr)
            call read_u_before_reset(file_id, number, stage, st)
        end if
        call h5gclose_f(stage_id, hdferr)
        if (.not. st%ok) call fatal_error(error, path//': cannot read '//trim(name)// &
                                          ' for the restart: HDF5 failed at '//st%failed, &
                                          io_error)
    end subroutine read_stored_stage

    !> The displacements zeroed by the RESETs up to stage `number`: stored with the last
    !> RESET stage up to it, zero before the first.
    subroutine read_u_before_reset(file_id, number, stage, st)
        integer(hid_t), intent(in) :: file_id
        integer, intent(in) :: number
        type(stage_result_t), intent(inout) :: stage
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: state_id
        character(len=30) :: name
        integer :: k, hdferr, nnode
        integer, allocatable :: ints(:)
        real(dp), allocatable :: reals(:)
        do k = number, 1, -1
            write (name, '(a,i4.4,a)') 'stages/stage_', k, '/state'
            call h5gopen_f(file_id, trim(name), state_id, hdferr)
            if (hdferr < 0) then
                call fail(st, trim(name))
                return
            end if
            call read_ints(state_id, 'ints', ints, st)
            if (st%ok) then
                if (ints(7) == 1) call read_reals(state_id, 'reals', reals, st)
            end if
            call h5gclose_f(state_id, hdferr)
            if (.not. st%ok) return
            nnode = ints(1)
            if (ints(7) == 1) then
                stage%carry%u_before_reset = reshape(reals(2*nnode + 1:4*nnode), [2, nnode])
                return
            end if
        end do
        allocate (stage%carry%u_before_reset(2, nnode), source=0.0_dp)
    end subroutine read_u_before_reset

    !> The solver's figures of the stage (its group `solver`).
    subroutine read_stats(stage_id, stage, st)
        integer(hid_t), intent(in) :: stage_id
        type(stage_result_t), intent(inout) :: stage
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: id
        integer :: hdferr
        call h5gopen_f(stage_id, 'solver', id, hdferr)
        if (hdferr < 0) then
            call fail(st, 'solver')
            return
        end if
        associate (s => stage%stats)
            s%neq = int_attribute(id, 'neq')
            s%nnz = int_attribute(id, 'nnz')
            s%t_pattern = real_attribute(id, 't_pattern', 0.0_dp)
            s%t_assembly = real_attribute(id, 't_assembly', 0.0_dp)
            s%t_symbolic = real_attribute(id, 't_symbolic', 0.0_dp)
            s%t_numeric = real_attribute(id, 't_numeric', 0.0_dp)
            s%t_update = real_attribute(id, 't_update', 0.0_dp)
            s%t_solve = real_attribute(id, 't_solve', 0.0_dp)
            s%t_contact = real_attribute(id, 't_contact', 0.0_dp)
            s%rcond = real_attribute(id, 'rcond', 0.0_dp)
            s%lu_nnz = int_attribute(id, 'lu_nnz')
            s%patterns = int_attribute(id, 'patterns')
            s%analyses = int_attribute(id, 'symbolic_factorisations')
            s%analyses_ahead = max(0, int_attribute(id, 'symbolic_ahead'))
            s%cholesky = int_attribute(id, 'cholesky')
            s%cholesky_declined = int_attribute(id, 'cholesky_declined')
            s%updates = int_attribute(id, 'updates')
            s%updates_declined = int_attribute(id, 'updates_declined')
            s%contact_iterations = int_attribute(id, 'contact_iterations')
            s%searches = int_attribute(id, 'searches')
            s%regularised = int_attribute(id, 'regularised')
            s%held = int_attribute(id, 'held')
            s%held_excess = real_attribute(id, 'held_excess', 0.0_dp)
        end associate
        call h5gclose_f(id, hdferr)
    end subroutine read_stats

    !> The carry from state/reals and state/ints (write_stage_state); u_before_reset is
    !> read by read_u_before_reset.
    subroutine read_carry(state_id, c, st)
        integer(hid_t), intent(in) :: state_id
        type(carry_t), intent(inout) :: c
        type(h5_state_t), intent(inout) :: st
        integer, allocatable :: ints(:)
        real(dp), allocatable :: reals(:)
        integer :: n(nlengths), r, i, nnode, nc
        c%prescribed_done = int_attribute(state_id, 'prescribed_done') == 1
        c%contact_scale = real_attribute(state_id, 'contact_scale', 1.0_dp)
        c%searches = int_attribute(state_id, 'searches')
        call read_ints(state_id, 'ints', ints, st)
        call read_reals(state_id, 'reals', reals, st)
        if (.not. st%ok) return
        n = ints(1:nlengths)
        nnode = n(1)
        nc = n(3)
        c%f_ext = reshape(reals(1:2*nnode), [2, nnode])
        r = 2*nnode + 2*nnode*n(7)
        i = nlengths
        if (n(8) == 1) then
            c%wetted = ints(i + 1:i + n(2)) == 1
            i = i + n(2)
        end if
        if (nc < 0) return
        c%p = take(nc)
        c%q = take(nc)
        c%g0 = take(nc)
        c%gap = take(nc)
        c%slip = take(nc)
        c%w = take(nc)
        c%wref = take(nc)
        c%g = take(nc)
        c%g_curve = take(nc)
        c%normal = reshape(take(2*nc), [2, nc])
        c%tangent = reshape(take(2*nc), [2, nc])
        c%cpl_a = take(n(4))
        c%u = reshape(take(2*nnode), [2, nnode])
        c%placed = next(nc) == 1
        c%supported = next(nc) == 1
        c%status = next(nc)
        c%slip_sign = next(nc)
        c%birth = next(nnode)
        c%cpl_ptr = next(nc + 1)
        c%cpl_node = next(n(4))
        if (n(5) >= 0) then
            c%seg_searched = next(n(5)) == 1
            c%mseg_searched = next(n(6)) == 1
        end if
        c%ngroup = ints(i + 1)
        i = i + 1
        c%tgroup = next(nc)
        c%grp_ptr = next(c%ngroup + 1)
        c%grp_node = next(c%grp_ptr(c%ngroup + 1) - 1)
        c%beta = take(nc)
    contains
        !> the next m reals
        function take(m) result(v)
            integer, intent(in) :: m
            real(dp) :: v(m)
            v = reals(r + 1:r + m)
            r = r + m
        end function take
        !> the next m integers
        function next(m) result(v)
            integer, intent(in) :: m
            integer :: v(m)
            v = ints(i + 1:i + m)
            i = i + m
        end function next
    end subroutine read_carry
end module cfrd_h5_state
