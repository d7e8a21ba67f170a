!> Tests of the result writers: what is written to HDF5 is read back unchanged through the
!> HDF5 library (reals round-trip bit for bit, so the tolerance is zero), the listing carries
!> the hand-made numbers, and an unwritable path is an io_error. Stages written behind the
!> analysis (cfrd_stage_writer) reach the file as handed over, on the second thread, each
!> reported after its write.
module test_io_results
    use hdf5, only: hid_t, hsize_t, h5open_f, h5close_f, h5fopen_f, h5fclose_f, h5dopen_f, &
                    h5dread_f, h5dclose_f, h5aopen_by_name_f, h5aread_f, h5aclose_f, &
                    h5lexists_f, h5fcreate_f, H5F_ACC_RDONLY_F, H5F_ACC_TRUNC_F, &
                    H5T_NATIVE_DOUBLE, H5T_NATIVE_INTEGER
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, io_error
    use cfrd_testing, only: unittest_t, new_unittest, check, fail
    use cfrd_model, only: model_t, gauge_t
    use cfrd_results, only: results_t, stage_result_t
    use cfrd_hdf5, only: write_results_h5, results_file_t, open_results_h5, write_stage_h5, &
                         close_results_h5, results_format_t
    use cfrd_xdmf, only: xml_escape
    use cfrd_h5_deflate, only: h5_open, registered, deflate_counts
    use cfrd_h5_datasets, only: h5_state_t, dataset_real1
    use cfrd_listing, only: write_listing, write_gauge_csv
    use cfrd_stage_summary, only: summarise_run
    use cfrd_test_models, only: new_model, elastic_material
    use cfrd_run_output, only: run_output_t, begin_output
    use cfrd_run_identity, only: run_identity_t
    use cfrd_stage_writer, only: write_stage_behind, wait_stage_writes, stage_writes_behind
    implicit none
    private

    public :: collect_io_results

    character(len=*), parameter :: dir = 'build/test-results/'

    !> test_written_behind's reports: the output written, and per report the stage number
    !> and the output's completed stages when it came
    type(run_output_t), pointer :: watched => null()
    integer, allocatable :: reported(:), completed_at_report(:)

contains

    subroutine collect_io_results(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('hdf5_round_trip', test_hdf5_round_trip), &
                new_unittest('hdf5_streamed_incomplete', test_hdf5_incomplete), &
                new_unittest('hdf5_lean_layout', test_hdf5_lean), &
                new_unittest('hdf5_libdeflate_filter', test_libdeflate), &
                new_unittest('xml_escape', test_xml_escape), &
                new_unittest('listing_tables', test_listing), &
                new_unittest('gauge_csv', test_gauge_csv), &
                new_unittest('unwritable_path_is_io_error', test_unwritable), &
                new_unittest('stages_written_behind', test_written_behind) &
                ]
    end subroutine collect_io_results

    !> Two quads on six nodes with made-up results whose every value is distinct.
    subroutine sample(model, results)
        type(model_t), intent(out) :: model
        type(results_t), intent(out) :: results
        integer :: i
        call new_model(model, reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 2.0_dp, 0.0_dp, &
                                       0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 2.0_dp, 1.0_dp], [2, 6]), &
                       reshape([1, 2, 5, 4, 2, 3, 6, 5], [4, 2]), [1, 2], &
                       [elastic_material(1.0e4_dp, 0.3_dp, 20.0_dp), &
                        elastic_material(2.0e4_dp, 0.2_dp, 21.0_dp)])
        model%deck_text = 'TITLE     sample'//new_line('a')//'END'
        model%fixed(:, 1:3) = .true.
        model%gauges = [gauge_t('C3-V7', 5, 'top middle')]
        allocate (results%stages(1))
        associate (s => results%stages(1))
            s%name = 'LOADS'
            s%active = [.true., .true.]
            s%stress_level = [0.5_dp, 0.97_dp]
            s%near_failure = 1
            s%displacement = reshape([(0.001_dp*i, i=1, 12)], [2, 6])
            s%displacement_total = s%displacement + 1.0_dp
            s%date = '1997-05'
            s%water_level = 660.0_dp
            s%reaction = 0.0_dp*s%displacement
            s%reaction(:, 1:3) = reshape([1.5_dp, 10.0_dp, -0.5_dp, 20.0_dp, -1.0_dp, 12.0_dp], &
                                         [2, 3])
            s%stress_gauss = reshape([(-1.0_dp*i, i=1, 32)], [4, 4, 2])
            s%history_gauss = reshape([(0.01_dp*i, i=1, 16)], [2, 4, 2])
            s%stress_centroid = reshape([(-2.0_dp*i, i=1, 8)], [4, 2])
            s%principal = reshape([(-3.0_dp*i, i=1, 6)], [3, 2])
            s%reaction_sum = [0.0_dp, 42.0_dp]
            s%applied_load = [0.0_dp, -42.0_dp]
            s%stats%neq = 6
            s%stats%nnz = 36
            s%stats%rcond = 0.125_dp
        end associate
        results%wall_time = 0.5_dp
    end subroutine sample

    subroutine test_hdf5_round_trip(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        integer(hid_t) :: file_id, dset_id, attr_id
        real(dp) :: u(2, 6), sg(4, 4, 2), x(2, 6), load(2), rcond
        integer :: conn(4, 2), neq, hdferr
        call sample(model, results)
        call execute_command_line('mkdir -p '//dir)
        call write_results_h5(dir//'sample.h5', model, results, error)
        if (allocated(error)) return
        call open_written(dir//'sample.h5', 'the written file', file_id, error)
        if (allocated(error)) return
        call h5dopen_f(file_id, 'mesh/coordinates', dset_id, hdferr)
        call h5dread_f(dset_id, H5T_NATIVE_DOUBLE, x, [2_hsize_t, 6_hsize_t], hdferr)
        call h5dclose_f(dset_id, hdferr)
        call h5dopen_f(file_id, 'mesh/connectivity', dset_id, hdferr)
        call h5dread_f(dset_id, H5T_NATIVE_INTEGER, conn, [4_hsize_t, 2_hsize_t], hdferr)
        call h5dclose_f(dset_id, hdferr)
        call h5dopen_f(file_id, 'stages/stage_0001/displacement', dset_id, hdferr)
        call h5dread_f(dset_id, H5T_NATIVE_DOUBLE, u, [2_hsize_t, 6_hsize_t], hdferr)
        call h5dclose_f(dset_id, hdferr)
        call h5dopen_f(file_id, 'stages/stage_0001/stress_gauss', dset_id, hdferr)
        call h5dread_f(dset_id, H5T_NATIVE_DOUBLE, sg, [4_hsize_t, 4_hsize_t, 2_hsize_t], hdferr)
        call h5dclose_f(dset_id, hdferr)
        call h5aopen_by_name_f(file_id, 'stages/stage_0001', 'applied_load', attr_id, hdferr)
        call h5aread_f(attr_id, H5T_NATIVE_DOUBLE, load, [2_hsize_t], hdferr)
        call h5aclose_f(attr_id, hdferr)
        call h5aopen_by_name_f(file_id, 'stages/stage_0001/solver', 'neq', attr_id, hdferr)
        call h5aread_f(attr_id, H5T_NATIVE_INTEGER, neq, [1_hsize_t], hdferr)
        call h5aclose_f(attr_id, hdferr)
        call h5aopen_by_name_f(file_id, 'stages/stage_0001/solver', 'rcond', attr_id, hdferr)
        call h5aread_f(attr_id, H5T_NATIVE_DOUBLE, rcond, [1_hsize_t], hdferr)
        call h5aclose_f(attr_id, hdferr)
        call h5fclose_f(file_id, hdferr)
        call h5close_f(hdferr)
        associate (s => results%stages(1))
            call check(error, all(x == model%mesh%x), 'coordinates read back')
            if (allocated(error)) return
            call check(error, all(conn == model%mesh%conn), 'connectivity read back')
            if (allocated(error)) return
            call check(error, all(u == s%displacement), 'displacements read back')
            if (allocated(error)) return
            call check(error, all(sg == s%stress_gauss), 'Gauss-point stresses read back')
            if (allocated(error)) return
            call check(error, all(load == s%applied_load), 'applied load attribute')
            if (allocated(error)) return
            call check(error, neq, 6, 'neq attribute')
            if (allocated(error)) return
            call check(error, rcond, 0.125_dp, 'rcond attribute', abs=0.0_dp)
        end associate
    end subroutine test_hdf5_round_trip

    !> A run that stops after its first of two stages: the file closed without `complete`
    !> says so (complete = 0, stages_completed = 1, stages_total = 2, the failure) and its
    !> stage reads back bit for bit, with the history and (--results full) the z-padded
    !> displacements; the file written whole says complete = 1.
    subroutine test_hdf5_incomplete(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        type(results_file_t) :: file
        integer(hid_t) :: file_id
        real(dp) :: history(2, 4, 2), u3(3, 6)
        integer :: complete, completed, total, hdferr
        call sample(model, results)
        model%stages = [model%stages(1), model%stages(1)]
        call execute_command_line('mkdir -p '//dir)
        call open_results_h5(file, dir//'partial.h5', model, error, &
                             format=results_format_t(full=.true.))
        if (.not. allocated(error)) call write_stage_h5(file, 1, results%stages(1), error)
        if (allocated(error)) then
            call close_results_h5(file, .false.)
            return
        end if
        call close_results_h5(file, .false., error, failure='stopped by the test')
        if (allocated(error)) return
        call open_written(dir//'partial.h5', 'the partial file', file_id, error)
        if (allocated(error)) return
        complete = read_int_attr(file_id, '.', 'complete')
        completed = read_int_attr(file_id, '.', 'stages_completed')
        total = read_int_attr(file_id, '.', 'stages_total')
        history = reshape(read_doubles(file_id, 'stages/stage_0001/history_gauss', 16), &
                          shape(history))
        u3 = reshape(read_doubles(file_id, 'stages/stage_0001/displacement_total_xyz', 18), &
                     shape(u3))
        call h5fclose_f(file_id, hdferr)
        call h5close_f(hdferr)     ! the writer opens and closes the library itself
        call check(error, complete, 0, 'complete of a file closed incomplete')
        if (allocated(error)) return
        call check(error, completed, 1, 'stages_completed')
        if (allocated(error)) return
        call check(error, total, 2, 'stages_total')
        if (allocated(error)) return
        call check(error, all(history == results%stages(1)%history_gauss), &
                   'Gauss-point history read back')
        if (allocated(error)) return
        call check(error, all(u3(1:2, :) == results%stages(1)%displacement_total) .and. &
                   all(u3(3, :) == 0.0_dp), 'displacement_total_xyz = (ux, uy, 0)')
        if (allocated(error)) return
        call write_results_h5(dir//'whole.h5', model, results, error)
        if (allocated(error)) return
        call h5open_f(hdferr)
        call h5fopen_f(dir//'whole.h5', H5F_ACC_RDONLY_F, file_id, hdferr)
        complete = read_int_attr(file_id, '.', 'complete')
        call h5fclose_f(file_id, hdferr)
        call h5close_f(hdferr)
        call check(error, complete, 1, 'complete of a file written whole')
    contains
        integer function read_int_attr(loc, object, name) result(value)
            integer(hid_t), intent(in) :: loc
            character(len=*), intent(in) :: object, name
            integer(hid_t) :: attr_id
            integer :: err
            value = -1
            call h5aopen_by_name_f(loc, object, name, attr_id, err)
            if (err < 0) return
            call h5aread_f(attr_id, H5T_NATIVE_INTEGER, value, [1_hsize_t], err)
            call h5aclose_f(attr_id, err)
        end function read_int_attr


    end subroutine test_hdf5_incomplete

    !> The lean layout (the default; docs/results.md "What is written"): two stages with
    !> the same made-up fields. Read back through the HDF5 library: the second stage's
    !> Gauss-point stresses are its own values (a link to the first stage's); the derived
    !> datasets (stress_centroid, principal, displacement_total, the z-padded copies) are
    !> absent; with --results full they are there, the centroid stresses bit for bit.
    subroutine test_hdf5_lean(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        integer(hid_t) :: file_id
        integer :: hdferr, k
        real(dp) :: sg(4, 4, 2), centroid(4, 2)
        logical :: there(5), full_there(5)
        character(len=*), parameter :: derived(5) = [character(len=22) :: 'stress_centroid', &
            'principal', 'displacement_total', 'displacement_xyz', 'displacement_total_xyz']
        call sample(model, results)
        model%stages = [model%stages(1), model%stages(1)]
        results%stages = [results%stages(1), results%stages(1)]
        call execute_command_line('mkdir -p '//dir)
        call write_results_h5(dir//'lean.h5', model, results, error)
        if (allocated(error)) return
        call h5open_f(hdferr)
        call h5fopen_f(dir//'lean.h5', H5F_ACC_RDONLY_F, file_id, hdferr)
        sg = reshape(read_doubles(file_id, 'stages/stage_0002/stress_gauss', 32), shape(sg))
        do k = 1, 5
            call h5lexists_f(file_id, 'stages/stage_0002/'//trim(derived(k)), there(k), hdferr)
        end do
        call h5fclose_f(file_id, hdferr)
        call h5close_f(hdferr)
        call check(error, all(sg == results%stages(2)%stress_gauss), &
                   'stress_gauss of stage 2 read back (linked to stage 1)')
        if (allocated(error)) return
        call check(error, .not. any(there), 'no derived datasets in a lean file')
        if (allocated(error)) return
        call write_results_h5(dir//'full.h5', model, results, error, &
                              format=results_format_t(full=.true.))
        if (allocated(error)) return
        call h5open_f(hdferr)
        call h5fopen_f(dir//'full.h5', H5F_ACC_RDONLY_F, file_id, hdferr)
        do k = 1, 5
            call h5lexists_f(file_id, 'stages/stage_0002/'//trim(derived(k)), full_there(k), &
                             hdferr)
        end do
        centroid = reshape(read_doubles(file_id, 'stages/stage_0002/stress_centroid', 8), &
                           [4, 2])
        call h5fclose_f(file_id, hdferr)
        call h5close_f(hdferr)
        call check(error, all(full_there) .and. &
                   all(centroid == results%stages(2)%stress_centroid), &
                   'derived datasets in a full file')
    end subroutine test_hdf5_lean

    !> A dataset of doubles of any shape into `values` (its size, in the file's order), -1
    !> everywhere when it cannot be read.
    function read_doubles(loc, name, n) result(values)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        integer, intent(in) :: n
        real(dp) :: values(n)
        integer(hid_t) :: dset_id
        integer :: err
        values = -1.0_dp
        call h5dopen_f(loc, name, dset_id, err)
        if (err < 0) return
        call h5dread_f(dset_id, H5T_NATIVE_DOUBLE, values, [int(n, hsize_t)], err)
        call h5dclose_f(dset_id, err)
    end function read_doubles

    !> The deflate filter is libdeflate's (src/io/cfrd_h5_deflate.c) after every h5_open,
    !> H5close between: 200,000 distinct doubles written at levels 1 and 9 through
    !> cfrd_h5_datasets (two chunks each, shuffle + deflate), the library closed and opened
    !> again, read back bit for bit (the reference: the values written); the filter's own
    !> counts say it compressed and decompressed the 4 chunks and never failed. That the
    !> chunks are zlib streams any reader inflates is tools/check_deflate.py's.
    subroutine test_libdeflate(error)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: n = 200000
        type(h5_state_t) :: st
        integer(hid_t) :: file_id
        integer :: hdferr, i, d0, i0, f0, d1, i1, f1, d2, i2, f2
        real(dp), allocatable :: x(:), back(:, :)   ! on the heap: 4.8 MB
        allocate (x(n), back(n, 2))
        x = [(1.0e3_dp*sin(1.0e-3_dp*i) + 0.1_dp*i, i=1, n)]
        call execute_command_line('mkdir -p '//dir)
        call deflate_counts(d0, i0, f0)
        call h5_open(hdferr)
        call check(error, hdferr >= 0 .and. registered(), 'libdeflate registered as deflate')
        if (allocated(error)) return
        call h5fcreate_f(dir//'libdeflate.h5', H5F_ACC_TRUNC_F, file_id, hdferr)
        st%deflate = 1
        call dataset_real1(file_id, 'level1', x, 'm', 'x', st)
        st%deflate = 9
        call dataset_real1(file_id, 'level9', x, 'm', 'x', st)
        call h5fclose_f(file_id, hdferr)
        call h5close_f(hdferr)
        call check(error, st%ok, 'the two datasets written')
        if (allocated(error)) return
        call deflate_counts(d1, i1, f1)
        call h5_open(hdferr)
        call h5fopen_f(dir//'libdeflate.h5', H5F_ACC_RDONLY_F, file_id, hdferr)
        back(:, 1) = read_doubles(file_id, 'level1', n)
        back(:, 2) = read_doubles(file_id, 'level9', n)
        call h5fclose_f(file_id, hdferr)
        call h5close_f(hdferr)
        call deflate_counts(d2, i2, f2)
        call check(error, d1 - d0, 4, 'chunks compressed by libdeflate')
        if (allocated(error)) return
        call check(error, i2 - i1, 4, 'chunks decompressed by libdeflate after H5close')
        if (allocated(error)) return
        call check(error, f2 - f0, 0, 'failures of the filter')
        if (allocated(error)) return
        call check(error, all(back(:, 1) == x) .and. all(back(:, 2) == x), &
                   'values read back bit for bit')
    end subroutine test_libdeflate

    !> XML's five special characters in a stage label or title are escaped (XML 1.0, 2.4).
    subroutine test_xml_escape(error)
        type(error_t), allocatable, intent(out) :: error
        call check(error, xml_escape('FILL <B1> "a" & ''b''') == &
                   'FILL &lt;B1&gt; &quot;a&quot; &amp; &apos;b&apos;', 'escaped text')
    end subroutine test_xml_escape

    !> The listing prints the reaction sums and a node's displacement: read them back.
    subroutine test_listing(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        character(len=200) :: line
        integer :: unit, stat, node
        real(dp) :: a, b, ux, uy
        logical :: found_sum, found_node
        call sample(model, results)
        call execute_command_line('mkdir -p '//dir)
        call write_listing(dir//'sample.out', model, summarise_run(model, results), &
                           results%stages(1), results%wall_time, error)
        if (allocated(error)) return
        found_sum = .false.
        found_node = .false.
        open (newunit=unit, file=dir//'sample.out', status='old', action='read')
        do
            read (unit, '(a)', iostat=stat) line
            if (stat /= 0) exit
            if (line(1:8) == '    SUM ') then
                read (line(9:), *) a, b
                ! Hand sum of the sample reactions: (1.5 - 0.5 - 1.0, 10 + 20 + 12) = (0, 42);
                ! printed with 6 decimals in es15.6: relative 1e-6.
                call check(error, b, 42.0_dp, 'sum of y reactions', rel=1e-6_dp)
                if (allocated(error)) return
                found_sum = .true.
            else if (index(line, 'NODE DISPLACEMENTS') > 0) then
                read (unit, '(a)') line
                read (unit, '(a)') line
                read (unit, '(a)') line      ! node 2
                read (line, *) node, a, b, ux, uy
                ! Node 2 moves (0.003, 0.004) by construction of the sample.
                call check(error, node, 2, 'second row is node 2')
                if (allocated(error)) return
                call check(error, uy, 0.004_dp, 'uy of node 2', rel=1e-6_dp)
                if (allocated(error)) return
                found_node = .true.
            end if
        end do
        close (unit)
        call check(error, found_sum .and. found_node, 'SUM line and displacement table found')
    end subroutine test_listing

    !> The gauge CSV holds each gauge's ux and settlement (-uy) since placement: node 5 of the
    !> sample has displacement_total = (0.009, 0.010) + 1 by construction; 10 significant
    !> digits are written, so 1e-9 relative.
    subroutine test_gauge_csv(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        character(len=400) :: header, line
        real(dp) :: ux, settlement
        integer :: unit, comma(5), k, pos
        call sample(model, results)
        call execute_command_line('mkdir -p '//dir)
        call write_gauge_csv(dir//'sample-gauges.csv', model, summarise_run(model, results), &
                             error)
        if (allocated(error)) return
        open (newunit=unit, file=dir//'sample-gauges.csv', status='old', action='read')
        read (unit, '(a)') header
        read (unit, '(a)') line
        close (unit)
        call check(error, trim(header) == 'stage,label,date,water_level_m,C3-V7_ux_m,'// &
                   'C3-V7_settlement_m', 'CSV header')
        if (allocated(error)) return
        ! Fields: stage, "label", date, level, ux, settlement (the label has no comma).
        pos = 0
        do k = 1, 5
            comma(k) = pos + index(line(pos + 1:), ',')
            pos = comma(k)
        end do
        read (line(comma(4) + 1:comma(5) - 1), *) ux
        read (line(comma(5) + 1:), *) settlement
        call check(error, line(comma(2) + 1:comma(4) - 1) == '1997-05,660.00', &
                   'date and level fields')
        if (allocated(error)) return
        call check(error, ux, 1.009_dp, 'ux of the gauge', rel=1e-9_dp)
        if (allocated(error)) return
        call check(error, settlement, -1.010_dp, 'settlement of the gauge', rel=1e-9_dp)
    end subroutine test_gauge_csv

    subroutine test_unwritable(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        integer :: category
        call sample(model, results)
        call write_listing(dir//'no/such/dir/x.out', model, summarise_run(model, results), &
                           results%stages(1), results%wall_time, error)
        if (.not. allocated(error)) then
            call fail(error, 'listing into a missing directory succeeded')
            return
        end if
        category = error%category
        call check(error, category, io_error, 'listing error category')
        if (allocated(error)) return
        call write_results_h5(dir//'no/such/dir/x.h5', model, results, error)
        if (.not. allocated(error)) then
            call fail(error, 'HDF5 file in a missing directory succeeded')
            return
        end if
        category = error%category
        call check(error, category, io_error, 'HDF5 error category')
    end subroutine test_unwritable
    !> Three stages handed to the writer behind the analysis: the first two are written by
    !> the second thread (unless CFRD_WRITE_BEHIND=0 runs them on the caller), in order, and
    !> each as it was when handed over: the first's displacements are changed after its
    !> hand-over, and the file holds the values before the change (reference: the values
    !> handed over, bit for bit); the last is written on the caller's thread before the call
    !> returns. Each is reported after its write. A write to the closed file is an
    !> io_error, returned by the wait.
    subroutine test_written_behind(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        type(run_output_t), target :: out
        type(error_t), allocatable :: write_error
        character(len=32) :: setting
        integer(hid_t) :: file_id
        real(dp), allocatable :: before(:, :), after(:, :)
        integer :: jobs, hdferr, length, behind, completed_last
        call sample(model, results)
        model%stages = [model%stages(1), model%stages(1), model%stages(1)]
        call execute_command_line('mkdir -p '//dir)
        call begin_output(out, dir//'behind', model, &
                          run_identity_t(run_id='test', deck_sha256=repeat('0', 64), &
                                         deck_path='behind.dat', started='2026-11-28', &
                                         host='test', pid=1, start_ticks=''), error, .false.)
        if (allocated(error)) return
        jobs = stage_writes_behind()
        before = results%stages(1)%displacement
        watched => out
        reported = [integer ::]
        completed_at_report = [integer ::]
        ! stages 1 and 2 of 3: written behind (the last stage of a run is written on the
        ! caller's thread: nothing is left to overlap)
        call write_stage_behind(out, model, 1, 3, results%stages(1), record_report)
        results%stages(1)%displacement = -results%stages(1)%displacement
        after = results%stages(1)%displacement
        call write_stage_behind(out, model, 2, 3, results%stages(1), record_report)
        call wait_stage_writes(write_error)
        behind = stage_writes_behind() - jobs
        ! stage 3 of 3, the last: written before the call returns, on this thread
        call write_stage_behind(out, model, 3, 3, results%stages(1), record_report)
        completed_last = out%completed
        call wait_stage_writes(write_error)
        call close_results_h5(out%h5, .false.)
        if (allocated(write_error)) then
            call move_alloc(write_error, error)
            return
        end if
        call check(error, completed_last, 3, 'the last stage written when the call returns')
        if (allocated(error)) return
        call check(error, size(reported) == 3, 'three reports')
        if (allocated(error)) return
        call check(error, all(reported == [1, 2, 3]) .and. &
                   all(completed_at_report == [1, 2, 3]), &
                   'each stage reported in order, after its write')
        if (allocated(error)) return
        call get_environment_variable('CFRD_WRITE_BEHIND', setting, length)
        if (trim(setting) /= '0') then
            call check(error, behind, 2, 'stages 1 and 2 written on the second thread')
            if (allocated(error)) return
            call check(error, stage_writes_behind() - jobs, 2, &
                       'the last stage written on the caller''s thread')
            if (allocated(error)) return
        end if
        call open_written(dir//'behind.h5.part', 'the file written behind', file_id, error)
        if (allocated(error)) return
        call check(error, all(reshape(read_doubles(file_id, 'stages/stage_0001/displacement', &
                                                   12), [2, 6]) == before), &
                   'stage 1 as handed over')
        if (.not. allocated(error)) &
            call check(error, all(reshape(read_doubles(file_id, &
                                                       'stages/stage_0002/displacement', 12), &
                                          [2, 6]) == after), 'stage 2 as handed over')
        if (.not. allocated(error)) &
            call check(error, all(reshape(read_doubles(file_id, &
                                                       'stages/stage_0003/displacement', 12), &
                                          [2, 6]) == after), 'stage 3 as given')
        call h5fclose_f(file_id, hdferr)
        call h5close_f(hdferr)
        if (allocated(error)) return
        ! the file is closed: the next write fails, and the wait says so
        call write_stage_behind(out, model, 2, 3, results%stages(1), record_report)
        call wait_stage_writes(write_error)
        call check(error, allocated(write_error), 'a failed write behind returns its error')
        if (allocated(error)) return
        call check(error, size(reported), 4, 'the failed write still reported')
        if (allocated(error)) return
        call check(error, write_error%category, io_error, 'the failed write is an io_error')
    end subroutine test_written_behind

    !> test_written_behind's report (on the writer's thread): the stage and the stages the
    !> output had completed when it came.
    !> Open `path` for reading (the HDF5 library opened first; the caller closes both); an
    !> error naming `what` when it cannot be opened.
    subroutine open_written(path, what, file_id, error)
        character(len=*), intent(in) :: path, what
        integer(hid_t), intent(out) :: file_id
        type(error_t), allocatable, intent(out) :: error
        integer :: hdferr
        call h5open_f(hdferr)
        call h5fopen_f(path, H5F_ACC_RDONLY_F, file_id, hdferr)
        if (hdferr < 0) call fail(error, 'cannot open '//what)
    end subroutine open_written

    subroutine record_report(number, total, stage)
        integer, intent(in) :: number, total
        type(stage_result_t), intent(in) :: stage
        reported = [reported, number]
        completed_at_report = [completed_at_report, watched%completed]
    end subroutine record_report
end module test_io_results
