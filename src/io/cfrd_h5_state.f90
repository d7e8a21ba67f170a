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
    use cfrd_h5_io, only: h5_state_t, fail, open_group, close_group, dataset_real1, &
                          dataset_real2, dataset_real3, dataset_int1, dataset_int2, &
                          attr_real, attr_int, set_attr_int
    use cfrd_h5_read, only: int_attribute, real_attribute, has_object, read_reals, read_ints, &
                            read_ints2
    implicit none
    private

    public :: write_stage_state, read_stored_stage, copy_stage

    !> The columns of state/contact/node_reals and node_flags.
    character(len=*), parameter :: contact_columns = 'p, q, g0, gap, slip, w, wref, g, '// &
        'g_curve, normal x, normal y, tangent x, tangent y'

contains

    !> The group `state` of the stage group `stage_id`.
    subroutine write_stage_state(stage_id, stage, st)
        integer(hid_t), intent(in) :: stage_id
        type(stage_result_t), intent(in) :: stage
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: id
        logical :: single
        single = st%single
        st%single = .false.
        call open_group(stage_id, 'state', id, st)
        associate (c => stage%carry)
            call attr_int(id, 'prescribed_done', merge(1, 0, c%prescribed_done), st)
            call attr_real(id, 'contact_scale', [c%contact_scale], st)
            ! it changes at RESET stages only: a stage without it has the last one's
            if (stage%kind == stage_reset) call dataset_real2(id, 'u_before_reset', &
                c%u_before_reset, 'm', 'ux, uy: the sum of the displacements at the RESETs', st)
            call dataset_real2(id, 'f_ext', c%f_ext, 'kN/m', 'fx, fy applied so far', st)
            if (allocated(c%wetted)) call dataset_int1(id, 'wetted', merge(1, 0, c%wetted), st)
            if (allocated(c%p)) call write_contact_state(id, c, st)
        end associate
        if (single) then
            ! the fields the next stage starts from, to the bit (the stage's are single)
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
    end subroutine write_stage_state

    !> The contact state (cfrd_contact's contact_t) under `state/contact`: per slave node
    !> the columns of `node_reals` and `node_flags` (contact_columns, contact_flags).
    subroutine write_contact_state(state_id, c, st)
        integer(hid_t), intent(in) :: state_id
        type(carry_t), intent(in) :: c
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: id
        real(dp), allocatable :: g_curve(:)
        integer :: nc
        nc = size(c%p)
        allocate (g_curve(nc), source=0.0_dp)
        if (allocated(c%g_curve)) g_curve = c%g_curve
        call open_group(state_id, 'contact', id, st)
        call attr_int(id, 'searches', c%searches, st)
        call dataset_real2(id, 'node_reals', transpose(reshape([c%p, c%q, c%g0, c%gap, &
                           c%slip, c%w, c%wref, c%g, g_curve, c%normal(1, :), &
                           c%normal(2, :), c%tangent(1, :), c%tangent(2, :)], [nc, 13])), &
                           'kPa, kPa, m, m, m, m, m, m2, m2, -, -, -, -', contact_columns, st)
        call dataset_int2(id, 'node_flags', transpose(reshape([merge(1, 0, c%placed), &
                          merge(1, 0, c%supported), c%status, c%slip_sign], [nc, 4])), st)
        if (allocated(c%seg_searched)) then
            call dataset_int1(id, 'seg_searched', merge(1, 0, c%seg_searched), st)
            call dataset_int1(id, 'mseg_searched', merge(1, 0, c%mseg_searched), st)
        end if
        call dataset_int1(id, 'birth', c%birth, st)
        call dataset_int1(id, 'cpl_ptr', c%cpl_ptr, st)
        call dataset_int1(id, 'cpl_node', c%cpl_node, st)
        call dataset_real1(id, 'cpl_a', c%cpl_a, 'm', 'coupling coefficients', st)
        call dataset_real2(id, 'u', c%u, 'm', 'ux, uy since placement', st)
        call close_group(id, st)
    end subroutine write_contact_state

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
                call read_reals(state_id, 'f_ext', stage%carry%f_ext, st)
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
        integer :: k, hdferr
        logical :: found
        do k = number, 1, -1
            write (name, '(a,i4.4,a)') 'stages/stage_', k, '/state'
            call h5gopen_f(file_id, trim(name), state_id, hdferr)
            if (hdferr < 0) then
                call fail(st, trim(name))
                return
            end if
            found = has_object(state_id, 'u_before_reset')
            if (found) call read_reals(state_id, 'u_before_reset', stage%carry%u_before_reset, st)
            call h5gclose_f(state_id, hdferr)
            if (found) return
        end do
        if (allocated(stage%displacement)) then
            allocate (stage%carry%u_before_reset, mold=stage%displacement)
            stage%carry%u_before_reset = 0.0_dp
        end if
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

    subroutine read_carry(state_id, c, st)
        integer(hid_t), intent(in) :: state_id
        type(carry_t), intent(inout) :: c
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: id
        integer :: hdferr
        integer, allocatable :: flags(:), flags2(:, :)
        real(dp), allocatable :: columns(:, :)
        c%prescribed_done = int_attribute(state_id, 'prescribed_done') == 1
        c%contact_scale = real_attribute(state_id, 'contact_scale', 1.0_dp)
        if (has_object(state_id, 'wetted')) then
            call read_ints(state_id, 'wetted', flags, st)
            c%wetted = flags == 1
        end if
        if (.not. has_object(state_id, 'contact')) return
        call h5gopen_f(state_id, 'contact', id, hdferr)
        if (hdferr < 0) then
            call fail(st, 'state/contact')
            return
        end if
        c%searches = int_attribute(id, 'searches')
        call read_reals(id, 'node_reals', columns, st)
        call read_ints2(id, 'node_flags', flags2, st)
        if (st%ok) then
            c%p = columns(1, :)
            c%q = columns(2, :)
            c%g0 = columns(3, :)
            c%gap = columns(4, :)
            c%slip = columns(5, :)
            c%w = columns(6, :)
            c%wref = columns(7, :)
            c%g = columns(8, :)
            c%g_curve = columns(9, :)
            c%normal = columns(10:11, :)
            c%tangent = columns(12:13, :)
            c%placed = flags2(1, :) == 1
            c%supported = flags2(2, :) == 1
            c%status = flags2(3, :)
            c%slip_sign = flags2(4, :)
        end if
        if (has_object(id, 'seg_searched')) then
            call read_ints(id, 'seg_searched', flags, st)
            c%seg_searched = flags == 1
            call read_ints(id, 'mseg_searched', flags, st)
            c%mseg_searched = flags == 1
        end if
        call read_ints(id, 'birth', c%birth, st)
        call read_ints(id, 'cpl_ptr', c%cpl_ptr, st)
        call read_ints(id, 'cpl_node', c%cpl_node, st)
        call read_reals(id, 'cpl_a', c%cpl_a, st)
        call read_reals(id, 'u', c%u, st)
        call h5gclose_f(id, hdferr)
    end subroutine read_carry
end module cfrd_h5_state
