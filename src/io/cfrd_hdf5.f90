!> The HDF5 results file (layout in docs/results.md): the deck, the program that made it,
!> the mesh with its groups and zones, and one group per stage with displacements,
!> reactions, Gauss-point stresses, strains and history, centroid and principal stresses,
!> stress levels, interface and slab results and the solver's figures, each with its units.
!> The file is written stage by stage (open_results_h5, write_stage_h5, close_results_h5)
!> and flushed after each stage, so that memory does not grow with the stages and a run
!> that stops half way leaves the completed stages readable; the root attribute `complete`
!> stays 0 until close_results_h5 says otherwise. Every HDF5 status is checked; the first
!> failure of a call is carried in `h5_state_t` (so later steps are skipped) and becomes an
!> error naming the object; close_results_h5 closes every handle whatever failed.
module cfrd_hdf5
    use, intrinsic :: iso_fortran_env, only: compiler_version
    use hdf5, only: hid_t, h5close_f, h5fcreate_f, h5fclose_f, h5fflush_f, &
                    h5gclose_f, h5eset_auto_f, H5F_ACC_TRUNC_F, H5F_SCOPE_GLOBAL_F, &
                    h5pcreate_f, h5pclose_f, h5pset_istore_k_f, H5P_FILE_CREATE_F, &
                    H5P_DEFAULT_F
    use cfrd_h5_deflate, only: h5_open
    use cfrd_kinds, only: dp
    use cfrd_h5_datasets, only: h5_state_t, fail, open_group, close_group, dataset_real1, &
                                dataset_real2, dataset_real3, dataset_int1, dataset_int2, &
                                dataset_text, dataset_names, attr_text, attr_real, attr_int, &
                                set_attr_int
    use cfrd_pjoint_io, only: write_pjoint_h5
    use cfrd_clock, only: iso_timestamp
    use cfrd_error, only: error_t, fatal_error, io_error
    use cfrd_version, only: cfrd_version_string
    use cfrd_model, only: model_t, stage_kind_name, dry_level, law_name, stage_reset
    use cfrd_results, only: results_t, stage_result_t
    use cfrd_interface_io, only: has_interfaces, has_slab, has_contact
    use cfrd_effects, only: effects_text
    use cfrd_run_identity, only: run_identity_t
    use cfrd_h5_state, only: write_stage_state
    use cfrd_h5_links, only: kept_t, real1_once, real2_once, real3_once
    use cfrd_element, only: element_t
    use cfrd_element_library, only: make_element
    implicit none
    private

    public :: results_file_t, results_format_t, open_results_h5, write_stage_h5, &
              close_results_h5
    public :: write_results_h5, layout_version

    !> Version of the layout of docs/results.md (2: streamed, `complete`, history, XDMF
    !> helpers, zones; 3: result sets: `run_id`, `deck_sha256`, `deck_path`, `set_files`;
    !> 4: each stage's restart state, group `state`).
    integer, parameter :: layout_version = 4

    !> How the values are stored (cfrd --compress, --float32; docs/results.md).
    type :: results_format_t
        !> deflate level of the datasets of min_filtered values or more: 0 (no filter,
        !> contiguous) to 9; the shuffle filter goes with any level above 0
        integer :: deflate = 1
        !> the stages' real datasets in IEEE single precision (about 7 digits), the mesh,
        !> the deck and every attribute in double
        logical :: single = .false.
        !> cfrd --results full: also what is derived or stored twice (stress_centroid,
        !> principal, displacement_total, displacement_xyz, displacement_total_xyz; what
        !> repeats written out at every stage, not linked): the layout before issue 21.
        !> Default (lean): those are left out or linked (docs/results.md)
        logical :: full = .false.
    end type results_format_t

    !> A results file open for writing, one stage after another.
    type :: results_file_t
        integer(hid_t) :: file_id = -1       !! -1: not open
        integer(hid_t) :: stages_id = -1     !! the /stages group
        integer :: stages_written = 0
        logical :: interfaces = .false.      !! the deck has interface elements
        logical :: slab = .false.            !! the deck has SLAB groups
        logical :: contact = .false.         !! the deck has CONTACT pairs
        type(results_format_t) :: format
        character(len=:), allocatable :: path
        !> lean files: the datasets stored once, linked while their values stay the same
        type(kept_t), allocatable :: kept(:)
    end type results_file_t

contains

    !> Write the results of a run held in memory to `path` (replacing it), complete;
    !> `format` as for open_results_h5.
    subroutine write_results_h5(path, model, results, error, format)
        character(len=*), intent(in) :: path
        type(model_t), intent(in) :: model
        type(results_t), intent(in) :: results
        type(error_t), allocatable, intent(out) :: error
        type(results_format_t), intent(in), optional :: format
        type(results_file_t) :: file
        integer :: s
        call open_results_h5(file, path, model, error, format=format)
        do s = 1, size(results%stages)
            if (allocated(error)) exit
            call write_stage_h5(file, s, results%stages(s), error)
        end do
        if (allocated(error)) then
            call close_results_h5(file, .false.)
        else
            call close_results_h5(file, .true., error, wall_time=results%wall_time)
        end if
    end subroutine write_results_h5

    !> Create the results file at `path` (replacing it) with the run's description (its
    !> `identity`: run id, the deck's SHA-256 and path, when given), the deck and the mesh,
    !> `complete` = 0 and no stage yet. After an error, call close_results_h5 all the same:
    !> it closes what was opened. `format`: how the values are stored (default: the
    !> filters at level 1, doubles).
    subroutine open_results_h5(file, path, model, error, identity, format)
        type(results_file_t), intent(out) :: file
        character(len=*), intent(in) :: path
        type(model_t), intent(in) :: model
        type(error_t), allocatable, intent(out) :: error
        type(run_identity_t), intent(in), optional :: identity
        type(results_format_t), intent(in), optional :: format
        type(h5_state_t) :: st
        integer(hid_t) :: group_id
        integer :: hdferr, m, width
        character(len=:), allocatable :: labels(:), laws(:)
        integer, allocatable :: counts(:, :)
        type(error_t), allocatable :: kind_error

        file%path = path
        if (present(format)) file%format = format
        st%deflate = file%format%deflate
        file%interfaces = has_interfaces(model)
        file%slab = has_slab(model)
        file%contact = has_contact(model)
        call h5_open(hdferr)
        if (hdferr < 0) then
            call fatal_error(error, 'cannot initialise the HDF5 library', io_error)
            return
        end if
        call h5eset_auto_f(0, hdferr)   ! our messages, not HDF5's error stack on stderr
        call create_file(path, file%file_id, hdferr)
        if (hdferr < 0) then
            file%file_id = -1
            call h5close_f(hdferr)
            call fatal_error(error, 'cannot create the results file '//path, io_error)
            return
        end if

        call attr_text(file%file_id, 'program', 'cfrd', st)
        call attr_text(file%file_id, 'version', cfrd_version_string, st)
        call attr_text(file%file_id, 'compiler', compiler_version(), st)
        call attr_int(file%file_id, 'layout_version', layout_version, st)
        call attr_text(file%file_id, 'title', model%title, st)
        call attr_text(file%file_id, 'deck_file', model%deck_file, st)
        if (present(identity)) then
            call attr_text(file%file_id, 'run_id', identity%run_id, st)
            call attr_text(file%file_id, 'deck_sha256', identity%deck_sha256, st)
            call attr_text(file%file_id, 'deck_path', identity%deck_path, st)
        end if
        call attr_text(file%file_id, 'effects', effects_text(model%effects), st)
        call attr_text(file%file_id, 'created', iso_timestamp(), st)
        call attr_text(file%file_id, 'units', 'm, kN, kPa', st)
        call attr_text(file%file_id, 'sign_convention', &
                       'tension positive; stress components xx, yy, zz, xy', st)
        call attr_text(file%file_id, 'numbering', &
                       'node and element numbers are 1-based as in the deck', st)
        call attr_int(file%file_id, 'stages_total', size(model%stages), st)
        call attr_int(file%file_id, 'stages_completed', 0, st)
        call attr_int(file%file_id, 'complete', 0, st)
        call attr_text(file%file_id, 'fields_precision', &
                       merge('float32', 'float64', file%format%single), st)
        call attr_int(file%file_id, 'deflate_level', file%format%deflate, st)
        call attr_text(file%file_id, 'results', merge('full', 'lean', file%format%full), st)

        call open_group(file%file_id, 'input', group_id, st)
        call dataset_text(group_id, 'deck', model%deck_text, st)
        call close_group(group_id, st)

        call open_group(file%file_id, 'mesh', group_id, st)
        call dataset_real2(group_id, 'coordinates', model%mesh%x, 'm', 'x, y', st)
        call dataset_int2(group_id, 'connectivity', model%mesh%conn, st)
        ! XDMF (ParaView) numbers nodes from 0 and reads datasets as they are.
        call dataset_int2(group_id, 'connectivity_zero_based', model%mesh%conn - 1, st)
        call dataset_int1(group_id, 'material', model%mesh%material, st)
        call dataset_int1(group_id, 'group', model%mesh%group, st)
        call dataset_int1(group_id, 'kind', model%mesh%kind, st)
        ! A lean file's XDMF computes stress_centroid from stress_gauss: it needs the
        ! divisor of each element's mean, its Gauss-point count (cfrd_xdmf).
        if (.not. file%format%full) then
            call gauss_point_counts(model, counts, kind_error)
            if (allocated(kind_error)) call fail(st, 'mesh/gauss_points: '// &
                                                 kind_error%message)
            if (allocated(counts)) call dataset_int2(group_id, 'gauss_points', counts, st)
        end if
        if (file%interfaces) then
            call dataset_int1(group_id, 'interface_elements', model%interfaces%element, st)
            call dataset_int1(group_id, 'interface_lines', model%interfaces%line, st)
            call dataset_int1(group_id, 'interface_method', model%interfaces%method, st)
        end if
        if (size(model%mesh%group_name) > 0) then
            call dataset_names(group_id, 'group_names', model%mesh%group_name, st)
        end if
        ! The zones: each material's label (IIA, IIIB, ... in the Tianshengqiao-I decks).
        if (size(model%materials) > 0) then
            width = 1
            do m = 1, size(model%materials)
                width = max(width, len(model%materials(m)%label), &
                            len(law_name(model%materials(m)%law)))
            end do
            allocate (character(len=width) :: labels(size(model%materials)), &
                      laws(size(model%materials)))
            do m = 1, size(model%materials)
                labels(m) = model%materials(m)%label
                laws(m) = law_name(model%materials(m)%law)
            end do
            call dataset_names(group_id, 'material_names', labels, st)
            call dataset_names(group_id, 'material_laws', laws, st)
        end if
        call close_group(group_id, st)

        if (allocated(model%gauges)) then
            if (size(model%gauges) > 0) then
                call open_group(file%file_id, 'gauges', group_id, st)
                call dataset_names(group_id, 'names', model%gauges%name, st)
                call dataset_int1(group_id, 'nodes', model%gauges%node, st)
                call close_group(group_id, st)
            end if
        end if

        call open_group(file%file_id, 'stages', file%stages_id, st)
        call flush_file(file, st)
        if (.not. st%ok) call fatal_error(error, 'cannot write the results file '//path// &
                                          ': HDF5 failed at '//st%failed, io_error)
    end subroutine open_results_h5

    !> Write stage `number` (its group stage_NNNN under /stages), count it in the root
    !> attribute `stages_completed`, and flush the file to disk.
    subroutine write_stage_h5(file, number, stage, error)
        type(results_file_t), intent(inout) :: file
        integer, intent(in) :: number
        type(stage_result_t), intent(in) :: stage
        type(error_t), allocatable, intent(out) :: error
        type(h5_state_t) :: st
        integer(hid_t) :: stage_id, solver_id
        character(len=16) :: stage_name
        real(dp), allocatable :: u3(:, :)
        logical :: lean
        character(len=:), allocatable :: path

        if (file%stages_id < 0) then
            call fatal_error(error, 'the results file is not open', io_error)
            return
        end if
        write (stage_name, '(a,i4.4)') 'stage_', number
        st%deflate = file%format%deflate
        st%single = file%format%single
        lean = .not. file%format%full
        path = '/stages/'//trim(stage_name)
        call open_group(file%stages_id, trim(stage_name), stage_id, st)
        call attr_text(stage_id, 'name', stage%name, st)
        call attr_text(stage_id, 'kind', stage_kind_name(stage%kind), st)
        if (allocated(stage%date)) call attr_text(stage_id, 'date', stage%date, st)
        call attr_int(stage_id, 'reservoir_empty', merge(1, 0, stage%water_level == dry_level), &
                      st)
        if (stage%water_level /= dry_level) &
            call attr_real(stage_id, 'water_level', [stage%water_level], st)
        ! The date as a day number since 1970-01-01, for time-dependent results (decks
        ! whose stage dates are in a date form; docs/results.md).
        if (stage%day > -huge(1.0_dp)) call attr_real(stage_id, 'day', [stage%day], st)
        call attr_int(stage_id, 'increments', stage%increments, st)
        call attr_int(stage_id, 'factorisations', stage%factorisations, st)
        call attr_int(stage_id, 'iterations', stage%iterations, st)
        call attr_int(stage_id, 'cutbacks', stage%cutbacks, st)
        call attr_real(stage_id, 'max_residual', [stage%max_residual], st)
        call attr_real(stage_id, 'wall_time', [stage%wall_time], st)
        call attr_int(stage_id, 'near_failure', stage%near_failure, st)
        call attr_real(stage_id, 'applied_load', stage%applied_load, st)
        call attr_real(stage_id, 'reaction_sum', stage%reaction_sum, st)
        call attr_text(stage_id, 'attribute_units', 'water_level m; max_residual -; '// &
                       'wall_time s; applied_load, reaction_sum kN/m (x, y)', st)
        call dataset_int1(stage_id, 'active', merge(1, 0, stage%active), st)
        call real1_once(file%kept, lean, stage_id, path, 'stress_level', stage%stress_level, &
                        '-', 'largest Gauss-point stress level of the element', st)
        call real2_once(file%kept, lean, stage_id, path, 'displacement', stage%displacement, &
                        'm', 'ux, uy', st)
        if (file%format%full) then
            call dataset_real2(stage_id, 'displacement_total', stage%displacement_total, 'm', &
                               'ux, uy since placement (RESETs added back)', st)
        else if (stage%kind == stage_reset .and. allocated(stage%carry%u_before_reset)) then
            ! lean: displacement_total = u_before_reset + displacement, computed by the
            ! readers (cfrdtools.results.field, the XDMF file) from this copy of the
            ! RESET's state/reals part (a RESET stage's; a few per deck)
            call dataset_real2(stage_id, 'u_before_reset', stage%carry%u_before_reset, 'm', &
                               'ux, uy zeroed by the RESETs up to this stage', st)
        end if
        if (file%format%full) then
            ! Three-component copies for XDMF (ParaView's vectors have three components);
            ! a lean file's XDMF pads the two-component datasets itself (cfrd_xdmf).
            allocate (u3(3, size(stage%displacement, 2)), source=0.0_dp)
            u3(1:2, :) = stage%displacement
            call dataset_real2(stage_id, 'displacement_xyz', u3, 'm', &
                               'ux, uy, 0 (displacement padded with z = 0 for XDMF)', st)
            u3(1:2, :) = stage%displacement_total
            call dataset_real2(stage_id, 'displacement_total_xyz', u3, 'm', &
                               'ux, uy, 0 (displacement_total padded with z = 0 for XDMF)', st)
            deallocate (u3)
        end if
        call real2_once(file%kept, lean, stage_id, path, 'reaction', stage%reaction, 'kN/m', &
                        'rx, ry', st)
        call real3_once(file%kept, lean, stage_id, path, 'stress_gauss', stage%stress_gauss, &
                        'kPa', 'xx, yy, zz, xy', st)
        ! Derived from stress_gauss: tools/cfrdtools/results.py recomputes them bit for bit
        ! (tools/check_results_lean.py); written with --results full.
        if (file%format%full) then
            call dataset_real2(stage_id, 'stress_centroid', stage%stress_centroid, 'kPa', &
                               'xx, yy, zz, xy', st)
            call dataset_real2(stage_id, 'principal', stage%principal, 'kPa, kPa, deg', &
                               'sigma1, sigma3, angle of sigma1 from x', st)
        end if
        if (allocated(stage%strain_gauss)) &
            call real3_once(file%kept, lean, stage_id, path, 'strain_gauss', &
                            stage%strain_gauss, '-, m', &
                            'xx, yy, zz, xy since placement (joints: du_n, du_s in m)', st)
        if (allocated(stage%history_gauss)) &
            call real3_once(file%kept, lean, stage_id, path, 'history_gauss', &
                            stage%history_gauss, '-', &
                            'past maximum of the E-B stress-state function SS = SL '// &
                            '(sigma3/pa)^(1/4), past maximum of the stress level SL '// &
                            '(zero for other laws)', st)
        if (allocated(stage%creep_gauss)) &
            call real3_once(file%kept, lean, stage_id, path, 'creep_gauss', stage%creep_gauss, &
                            '-', 'volumetric and generalised shear creep strain reached '// &
                            '(compression positive; zero where the material does not '// &
                            'creep)', st)
        if (allocated(stage%wetting_gauss)) &
            call real3_once(file%kept, lean, stage_id, path, 'wetting_gauss', &
                            stage%wetting_gauss, '-', &
                            'volumetric and generalised shear wetting strain reached '// &
                            '(compression positive; zero where nothing was wetted)', st)
        call write_interface_stage(stage_id, path, file, stage, st)
        call write_pjoint_h5(stage_id, stage, st)
        ! what a restart from this stage needs (docs/results.md, "Restart")
        if (allocated(stage%carry%f_ext)) call write_stage_state(stage_id, stage, st, &
                                                                 .not. file%format%full)
        call open_group(stage_id, 'solver', solver_id, st)
        call attr_int(solver_id, 'neq', stage%stats%neq, st)
        call attr_int(solver_id, 'nnz', stage%stats%nnz, st)
        call attr_real(solver_id, 't_pattern', [stage%stats%t_pattern], st)
        call attr_real(solver_id, 't_assembly', [stage%stats%t_assembly], st)
        call attr_real(solver_id, 't_symbolic', [stage%stats%t_symbolic], st)
        call attr_real(solver_id, 't_numeric', [stage%stats%t_numeric], st)
        call attr_real(solver_id, 't_update', [stage%stats%t_update], st)
        call attr_real(solver_id, 't_solve', [stage%stats%t_solve], st)
        call attr_real(solver_id, 't_contact', [stage%stats%t_contact], st)
        call attr_real(solver_id, 'rcond', [stage%stats%rcond], st)
        call attr_int(solver_id, 'lu_nnz', stage%stats%lu_nnz, st)
        call attr_int(solver_id, 'patterns', stage%stats%patterns, st)
        call attr_int(solver_id, 'symbolic_factorisations', stage%stats%analyses, st)
        call attr_int(solver_id, 'symbolic_ahead', stage%stats%analyses_ahead, st)
        call attr_int(solver_id, 'numeric_factorisations', stage%factorisations, st)
        call attr_int(solver_id, 'cholesky', stage%stats%cholesky, st)
        call attr_int(solver_id, 'cholesky_declined', stage%stats%cholesky_declined, st)
        call attr_int(solver_id, 'updates', stage%stats%updates, st)
        call attr_int(solver_id, 'updates_declined', stage%stats%updates_declined, st)
        call attr_int(solver_id, 'contact_iterations', stage%stats%contact_iterations, st)
        call attr_int(solver_id, 'searches', stage%stats%searches, st)
        call attr_int(solver_id, 'regularised', stage%stats%regularised, st)
        call attr_int(solver_id, 'held', stage%stats%held, st)
        call attr_real(solver_id, 'held_excess', [stage%stats%held_excess], st)
        call close_group(solver_id, st)
        call close_group(stage_id, st)
        if (st%ok) then
            file%stages_written = number
            call set_attr_int(file%file_id, 'stages_completed', number, st)
        end if
        call flush_file(file, st)
        if (.not. st%ok) call fatal_error(error, 'cannot write the results file '// &
                                          file%path//': HDF5 failed at '//st%failed// &
                                          ' of '//trim(stage_name), io_error)
    end subroutine write_stage_h5

    !> Close the file: with `complete`, set the root attribute `complete` to 1; `wall_time`
    !> (s) goes to /run, `failure` (why the run stopped) and `set_files` (the files of the
    !> result set) to the root. Closes every handle whatever fails; does nothing when the
    !> file is not open.
    subroutine close_results_h5(file, complete, error, wall_time, failure, set_files)
        type(results_file_t), intent(inout) :: file
        logical, intent(in) :: complete
        type(error_t), allocatable, intent(out), optional :: error
        real(dp), intent(in), optional :: wall_time
        character(len=*), intent(in), optional :: failure
        !> the names of the result set's files (without folder), one a line
        character(len=*), intent(in), optional :: set_files
        type(h5_state_t) :: st
        integer(hid_t) :: group_id
        integer :: hdferr
        if (file%file_id < 0) return
        if (present(failure)) call attr_text(file%file_id, 'failure', failure, st)
        if (present(set_files)) call attr_text(file%file_id, 'set_files', set_files, st)
        if (present(wall_time)) then
            call open_group(file%file_id, 'run', group_id, st)
            call attr_real(group_id, 'wall_time', [wall_time], st)
            call close_group(group_id, st)
        end if
        if (complete) call set_attr_int(file%file_id, 'complete', 1, st)
        if (file%stages_id >= 0) then
            call h5gclose_f(file%stages_id, hdferr)
            if (hdferr < 0) call fail(st, 'closing /stages')
            file%stages_id = -1
        end if
        call h5fclose_f(file%file_id, hdferr)
        if (hdferr < 0) call fail(st, 'closing the file')
        file%file_id = -1
        call h5close_f(hdferr)
        if (.not. st%ok .and. present(error)) call fatal_error(error, &
            'cannot write the results file '//file%path//': HDF5 failed at '//st%failed, &
            io_error)
    end subroutine close_results_h5

    subroutine flush_file(file, st)
        type(results_file_t), intent(in) :: file
        type(h5_state_t), intent(inout) :: st
        integer :: hdferr
        if (.not. st%ok) return
        call h5fflush_f(file%file_id, H5F_SCOPE_GLOBAL_F, hdferr)
        if (hdferr < 0) call fail(st, 'flushing the file')
    end subroutine flush_file

    !> The stage's interface stations, openings per slab phase and slab stresses.
    subroutine write_interface_stage(stage_id, stage_path, file, stage, st)
        integer(hid_t), intent(in) :: stage_id
        character(len=*), intent(in) :: stage_path    !! /stages/stage_NNNN
        type(results_file_t), intent(inout) :: file
        type(stage_result_t), intent(in) :: stage
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: id
        integer :: n
        logical :: lean
        lean = .not. file%format%full
        if (file%interfaces) then
            call open_group(stage_id, 'interface', id, st)
            associate (r => stage%interface)
                call geometry('interface', r%x, r%y, r%s, 'station 1, 2 of each interface '// &
                              'element', 'station 1, 2', 'distance along the line')
                call dataset_real2(id, 'sigma_n', r%sigma_n, 'kPa', 'normal stress, tension +', st)
                call dataset_real2(id, 'tau', r%tau, 'kPa', 'shear stress along t', st)
                call dataset_real2(id, 'du_n', r%du_n, 'm', 'relative normal displacement, opening +', &
                                   st)
                call dataset_real2(id, 'du_s', r%du_s, 'm', 'relative tangential displacement', st)
                call dataset_int1(id, 'active', merge(1, 0, r%active), st)
            end associate
            n = size(stage%openings)
            if (n > 0) then
                call dataset_int1(id, 'opening_line', stage%openings%line, st)
                call dataset_int1(id, 'opening_group', stage%openings%group, st)
                call dataset_real1(id, 'opening_width', stage%openings%width, 'm', &
                                   'largest relative normal displacement of the phase', st)
                call dataset_real1(id, 'opening_depth', stage%openings%depth, 'm', &
                                   'down-slope length of the tensile zone from the top', st)
            end if
            call close_group(id, st)
        end if
        if (file%contact) then
            call open_group(stage_id, 'contact', id, st)
            associate (r => stage%contact)
                call dataset_int1(id, 'node', r%node, st)
                call dataset_int1(id, 'pair', r%pair, st)
                call dataset_int1(id, 'group', r%group, st)
                call dataset_int1(id, 'placed', merge(1, 0, r%placed), st)
                call dataset_int1(id, 'status', r%status, st)
                call real1_once(file%kept, lean, id, stage_path//'/contact', 'x', r%x, 'm', &
                                'slave node, as meshed', st, key='contact/x')
                call real1_once(file%kept, lean, id, stage_path//'/contact', 'y', r%y, 'm', &
                                'slave node, as meshed', st, key='contact/y')
                call real1_once(file%kept, lean, id, stage_path//'/contact', 's', r%s, 'm', &
                                'along the slave surface', st, key='contact/s')
                call dataset_real1(id, 'gap', r%gap, 'm', 'normal gap, open +', st)
                call dataset_real1(id, 'slip', r%slip, 'm', 'accumulated slip along t', st)
                call dataset_real1(id, 'sigma_n', r%sigma_n, 'kPa', &
                                   'normal contact traction, tension +', st)
                call dataset_real1(id, 'tau', r%tau, 'kPa', 'shear traction on the slave along t', &
                                   st)
            end associate
            n = size(stage%openings)
            if (n > 0) then
                call dataset_int1(id, 'opening_pair', stage%openings%line, st)
                call dataset_int1(id, 'opening_group', stage%openings%group, st)
                call dataset_real1(id, 'opening_width', stage%openings%width, 'm', &
                                   'largest gap of the opening from the phase top', st)
                call dataset_real1(id, 'opening_depth', stage%openings%depth, 'm', &
                                   'length from the phase top down to where the gap closes', st)
                call dataset_real1(id, 'opening_max_gap', stage%openings%max_gap, 'm', &
                                   'largest gap anywhere in the slab phase', st)
            end if
            call close_group(id, st)
        end if
        if (file%slab) then
            call open_group(stage_id, 'slab', id, st)
            associate (r => stage%slab)
                call dataset_int1(id, 'element', r%element, st)
                call geometry('slab', r%x, r%y, r%s, 'Gauss points', 'Gauss points', &
                              'along the slab axis')
                call dataset_real2(id, 'sigma_t', r%sigma_t, 'kPa', 'along the axis', st)
                call dataset_real2(id, 'tau', r%tau, 'kPa', 'shear stress', st)
                call real1_once(file%kept, lean, id, stage_path//'/slab', 'section_s', &
                                r%section_s, 'm', 'section centre', st, key='slab/section_s')
                call real1_once(file%kept, lean, id, stage_path//'/slab', 'thickness', &
                                r%thickness, 'm', 'section thickness', st, key='slab/thickness')
                call dataset_real1(id, 'axial', r%axial, 'kN/m', 'N, tension +', st)
                call dataset_real1(id, 'shear', r%shear, 'kN/m', 'V', st)
                call dataset_real1(id, 'moment', r%moment, 'kN m/m', &
                                   'M, tension on the water side +', st)
                call real1_once(file%kept, lean, id, stage_path//'/slab', 'section_x', &
                                r%section_x, 'm', 'section centre', st, key='slab/section_x')
                call real1_once(file%kept, lean, id, stage_path//'/slab', 'section_y', &
                                r%section_y, 'm', 'section centre', st, key='slab/section_y')
                call dataset_real1(id, 'sigma_water', r%sigma_water, 'kPa', 'N/h + 6M/h^2', st)
                call dataset_real1(id, 'sigma_cushion', r%sigma_cushion, 'kPa', 'N/h - 6M/h^2', st)
                call real1_once(file%kept, lean, id, stage_path//'/slab', 'tensile_strength', &
                                r%tensile_strength, 'kPa', 'f_t', st, key='slab/tensile_strength')
                call dataset_real1(id, 'crack_ratio', r%crack_ratio, '-', 'sigma_1 / f_t', st)
            end associate
            call close_group(id, st)
        end if
    contains
        !> The stations' or Gauss points' x, y and s of `group`, stored once in a lean file.
        subroutine geometry(group, x, y, s, where_x, where_y, along)
            character(len=*), intent(in) :: group, where_x, where_y, along
            real(dp), intent(in) :: x(:, :), y(:, :), s(:, :)
            call real2_once(file%kept, lean, id, stage_path//'/'//group, 'x', x, 'm', where_x, &
                            st, key=group//'/x')
            call real2_once(file%kept, lean, id, stage_path//'/'//group, 'y', y, 'm', where_y, &
                            st, key=group//'/y')
            call real2_once(file%kept, lean, id, stage_path//'/'//group, 's', s, 'm', along, &
                            st, key=group//'/s')
        end subroutine geometry
    end subroutine write_interface_stage


    !> (4, nelem): each element's number of Gauss points (its element implementation's),
    !> repeated over the four stress components: the divisor of cfrd's stress_centroid
    !> (the stage driver's sum(stress(:, 1:ng, e))/ng) for the lean XDMF file.
    subroutine gauss_point_counts(model, counts, error)
        type(model_t), intent(in) :: model
        integer, allocatable, intent(out) :: counts(:, :)
        type(error_t), allocatable, intent(out) :: error
        class(element_t), allocatable :: element
        integer :: e
        allocate (counts(4, model%mesh%nelem))
        do e = 1, model%mesh%nelem
            if (e > 1) then
                if (model%mesh%kind(e) == model%mesh%kind(e - 1)) then
                    counts(:, e) = counts(:, e - 1)
                    cycle
                end if
            end if
            call make_element(model%mesh%kind(e), model%analysis, element, error)
            if (allocated(error)) return
            counts(:, e) = element%gauss_points()
        end do
    end subroutine gauss_point_counts

    !> Create `path` (replacing it) with B-tree nodes of at most 2 istore_k chunk entries for
    !> the chunked datasets [choice, docs/performance.md (am)]: HDF5 allocates every chunked
    !> dataset's first node whole, 2-3 kB at its default istore_k of 32, a tenth of a small
    !> deck's file; at istore_k 2 a node of four chunks takes 160-256 bytes. The file stays
    !> in the format of HDF5 1.8 (superblock version 1), which every HDF5 program reads.
    subroutine create_file(path, file_id, hdferr)
        character(len=*), intent(in) :: path
        integer(hid_t), intent(out) :: file_id
        integer, intent(out) :: hdferr
        integer, parameter :: istore_k = 2
        integer(hid_t) :: fcpl_id
        integer :: close_err
        file_id = -1
        call h5pcreate_f(H5P_FILE_CREATE_F, fcpl_id, hdferr)
        if (hdferr < 0) return
        call h5pset_istore_k_f(fcpl_id, istore_k, hdferr)
        if (hdferr >= 0) call h5fcreate_f(path, H5F_ACC_TRUNC_F, file_id, hdferr, fcpl_id, &
                                          H5P_DEFAULT_F)
        call h5pclose_f(fcpl_id, close_err)   ! a property list: nothing of the file
    end subroutine create_file
end module cfrd_hdf5
