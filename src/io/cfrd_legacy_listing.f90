!> The legacy-style listing (`cfrd --legacy-listing`, DECK.lst): the tables the legacy dam
!> codes (FEADAM, ISBILD) print after every layer, in fixed columns, so that an archived
!> listing and a cfrd run can be laid side by side and compared line by line (and read by
!> tools/compare.py). For every stage: the nodal point displacements since placement of
!> every node placed so far, and the stresses at the centroid, principal stresses, angle
!> and stress level of every active element. Layout and columns: docs/results.md.
module cfrd_legacy_listing
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, io_error
    use cfrd_version, only: cfrd_version_string
    use cfrd_model, only: model_t, is_joint_kind
    use cfrd_results, only: stage_result_t
    use cfrd_columns, only: date_of, level_of
    use cfrd_fast_format, only: put_int, put_fixed, put_sci, next_line, write_lines, &
                                block_chars
    implicit none
    private

    public :: open_legacy_listing, append_legacy_stage, close_legacy_listing

contains

    !> Open the legacy-style listing at `path` and write its heading (with the `run_id` of
    !> its result set when given).
    subroutine open_legacy_listing(path, model, unit, error, run_id)
        character(len=*), intent(in) :: path
        type(model_t), intent(in) :: model
        integer, intent(out) :: unit
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: run_id
        integer :: stat
        character(len=256) :: msg
        open (newunit=unit, file=path, status='replace', action='write', iostat=stat, &
              iomsg=msg)
        if (stat == 0) write (unit, '(a)', iostat=stat, iomsg=msg) '1CFRD '// &
            cfrd_version_string//'   LEGACY-STYLE LISTING   DECK '//model%deck_file, &
            ' TITLE '//model%title, &
            ' UNITS M, KN, KPA; TENSION POSITIVE; DISPLACEMENTS SINCE EACH NODE''S PLACEMENT'
        if (stat == 0 .and. present(run_id)) &
            write (unit, '(a)', iostat=stat, iomsg=msg) ' RUN ID '//run_id
        ! Column 1 holds the carriage control of the line printers: '1' starts a page.
        if (stat /= 0) then
            call fatal_error(error, 'cannot write the legacy listing '//path//': '// &
                             trim(msg), io_error)
            unit = 0
        end if
    end subroutine open_legacy_listing

    !> Stage `s`'s tables: the displacements of the placed nodes, the centroid stresses of
    !> the active elements (written as each stage is done).
    subroutine append_legacy_stage(unit, path, model, s, st, error)
        integer, intent(in) :: unit, s
        character(len=*), intent(in) :: path
        type(model_t), intent(in) :: model
        type(stage_result_t), intent(in) :: st
        type(error_t), allocatable, intent(out) :: error
        integer :: stat, node, e, k, pos
        real(dp) :: angle
        logical, allocatable :: placed(:)
        character(len=256) :: msg
        character(len=:), allocatable :: buf
        associate (mesh => model%mesh)
            allocate (placed(mesh%nnode))
            write (unit, '(/,a,i5,2x,a,/,a,a10,a,a10,a,i7)', iostat=stat, iomsg=msg) '1STAGE', &
                s, st%name, ' DATE ', date_of(st), '   RESERVOIR (M) ', level_of(st), &
                '   ACTIVE ELEMENTS ', count(st%active)
            ! A node is placed once an active element uses it.
            placed = .false.
            do e = 1, mesh%nelem
                if (st%active(e)) placed(mesh%conn(:, e)) = .true.
            end do
            if (stat == 0) write (unit, '(/,a,/,a)', iostat=stat, iomsg=msg) &
                '  NODAL POINT DISPLACEMENTS', &
                '    NODE        X-ORD        Y-ORD       X-DISP       Y-DISP'
            ! The tables: the characters of the formats in the comments, made by
            ! cfrd_fast_format into blocks of lines written at once (docs/performance.md (r)).
            allocate (character(len=block_chars) :: buf)
            pos = 1
            do node = 1, mesh%nnode                     ! (i8,2f13.3,2es13.5)
                if (.not. placed(node) .or. stat /= 0) cycle
                call put_int(buf, pos, node, 8)
                call put_fixed(buf, pos, mesh%x(1, node), 13, 3)
                call put_fixed(buf, pos, mesh%x(2, node), 13, 3)
                call put_sci(buf, pos, printable(st%displacement_total(1, node)), 13, 5)
                call put_sci(buf, pos, printable(st%displacement_total(2, node)), 13, 5)
                call next_line(unit, buf, pos, stat, msg)
            end do
            call write_lines(unit, buf, pos, stat, msg)
            if (stat == 0) write (unit, '(/,a,/,a)', iostat=stat, iomsg=msg) &
                '  ELEMENT STRESSES AT CENTROIDS', &
                '    ELEM  MAT      SIGMA-X      SIGMA-Y      SIGMA-Z       TAU-XY'// &
                '      SIGMA-1      SIGMA-3   ANGLE  S-LEVEL'
            do e = 1, mesh%nelem
                ! Joints carry tractions: the main listing's INTERFACE table has them.
                if (.not. st%active(e) .or. is_joint_kind(mesh%kind(e)) .or. stat /= 0) cycle
                ! An angle that rounds to zero is printed as 0.00, never -0.00.
                angle = merge(0.0_dp, st%principal(3, e), abs(st%principal(3, e)) < 0.005_dp)
                call put_int(buf, pos, e, 8)                ! (i8,i5,6es13.5,f8.2,f9.4)
                call put_int(buf, pos, mesh%material(e), 5)
                do k = 1, size(st%stress_centroid, 1)
                    call put_sci(buf, pos, printable(st%stress_centroid(k, e)), 13, 5)
                end do
                call put_sci(buf, pos, printable(st%principal(1, e)), 13, 5)
                call put_sci(buf, pos, printable(st%principal(2, e)), 13, 5)
                call put_fixed(buf, pos, angle, 8, 2)
                call put_fixed(buf, pos, st%stress_level(e), 9, 4)
                call next_line(unit, buf, pos, stat, msg)
            end do
            call write_lines(unit, buf, pos, stat, msg)
        end associate
        if (stat /= 0) call fatal_error(error, 'cannot write the legacy listing '//path// &
                                        ': '//trim(msg), io_error)
    end subroutine append_legacy_stage

    !> The closing line, and close.
    subroutine close_legacy_listing(unit, path, error)
        integer, intent(in) :: unit
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: error
        integer :: stat
        character(len=256) :: msg
        write (unit, '(/,a)', iostat=stat, iomsg=msg) ' END OF LISTING'
        close (unit)
        if (stat /= 0) call fatal_error(error, 'cannot write the legacy listing '//path// &
                                        ': '//trim(msg), io_error)
    end subroutine close_legacy_listing

    !> Values below 1e-99 in magnitude as zero (Ew.d drops the E of a three-digit exponent),
    !> and never a negative zero.
    elemental real(dp) function printable(x)
        real(dp), intent(in) :: x
        printable = merge(0.0_dp, x, abs(x) < 1.0e-99_dp)
    end function printable
end module cfrd_legacy_listing
