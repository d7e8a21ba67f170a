!> Interface and slab results in words and tables (docs/results.md): the listing's opening
!> history, interface and slab tables, and the CSV files DECK-interface.csv (every station
!> at every stage), DECK-openings.csv (width and depth per slab phase and stage) and
!> DECK-slab.csv (section resultants per stage). Writers format; they compute nothing.
!> The station and section files are written stage by stage while the analysis runs
!> (`interface_csv_t`), the openings from the stages' summaries at the end.
module cfrd_interface_io
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, io_error
    use cfrd_model, only: model_t, dry_level, method_name
    use cfrd_results, only: stage_result_t, opening_t, slab_result_t
    use cfrd_stage_summary, only: stage_summary_t
    use cfrd_columns, only: run_id_comment, csv_real, date_of, level_of
    use cfrd_strings, only: to_text
    implicit none
    private

    public :: write_opening_history, write_interface_tables, write_openings_csv
    public :: write_opening_summary, has_interfaces, has_slab, has_contact, has_openings
    public :: phase_name, write_slab_history
    public :: interface_csv_t, open_interface_csv, append_interface_csv, close_interface_csv

    !> DECK-interface.csv and DECK-slab.csv, open while the analysis runs (unit 0: the deck
    !> has no interfaces, or no slab).
    type :: interface_csv_t
        integer :: interface_unit = 0, slab_unit = 0, contact_unit = 0
        character(len=:), allocatable :: interface_path, slab_path, contact_path
    end type interface_csv_t

    !> Contact node status names, by status 0 (open), 1 (stick), 2 (slip).
    character(len=5), parameter :: status_names(0:2) = ['open ', 'stick', 'slip ']

contains

    pure logical function has_interfaces(model)
        type(model_t), intent(in) :: model
        has_interfaces = .false.
        if (allocated(model%interfaces)) has_interfaces = size(model%interfaces) > 0
    end function has_interfaces

    !> The deck has CONTACT pairs (docs/cards.md, CONTACT).
    pure logical function has_contact(model)
        type(model_t), intent(in) :: model
        has_contact = .false.
        if (allocated(model%contact_pairs)) has_contact = size(model%contact_pairs) > 0
    end function has_contact

    !> Openings per slab phase are reported: from interface elements or from contact.
    pure logical function has_openings(model)
        type(model_t), intent(in) :: model
        has_openings = has_interfaces(model) .or. has_contact(model)
    end function has_openings

    pure logical function has_slab(model)
        type(model_t), intent(in) :: model
        has_slab = .false.
        if (allocated(model%slab_groups)) has_slab = size(model%slab_groups) > 0
    end function has_slab

    !> 'line L, GROUP' naming a slab phase's interface.
    function phase_name(model, op) result(text)
        type(model_t), intent(in) :: model
        type(opening_t), intent(in) :: op
        character(len=:), allocatable :: text
        character(len=12) :: number
        write (number, '(i0)') op%line
        text = 'line '//trim(number)//', '
        if (has_contact(model)) text = 'pair '//trim(number)//', '
        if (op%group > 0) then
            text = text//trim(model%mesh%group_name(op%group))
        else
            text = text//'(no group)'
        end if
    end function phase_name

    !> Per stage and slab phase: opening width and depth, extreme normal stresses.
    subroutine write_opening_history(unit, model, summaries)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        integer :: s, k
        if (.not. has_openings(model)) return
        if (has_contact(model)) then
            write (unit, '(/,a,/,a,/,a)') repeat('-', 100), ' CONTACT OPENINGS PER SLAB '// &
                'PHASE (width: largest gap; depth: length from the phase''s top down to '// &
                'where the gap closes)', repeat('-', 100)
        else
            write (unit, '(/,a,/,a,/,a)') repeat('-', 100), ' INTERFACE OPENINGS PER SLAB '// &
                'PHASE (width: largest relative normal displacement; depth: down-slope '// &
                'length of the tensile zone from the phase''s top)', repeat('-', 100)
        end if
        write (unit, '(a)') '  STAGE DATE       WATER (m) PHASE                    WIDTH (m)'// &
            '  DEPTH (m) LENGTH (m)  MIN SIGN (kPa)  MAX SIGN (kPa)'
        do s = 1, size(summaries)
            associate (st => summaries(s))
                do k = 1, size(st%openings)
                    associate (op => st%openings(k))
                        write (unit, '(i7,1x,a10,a10,1x,a24,3f11.4,2es16.5)') s, date_of(st), &
                            level_of(st), phase_name(model, op), op%width, op%depth, &
                            op%length, op%max_compression, op%max_tension
                    end associate
                end do
            end associate
        end do
    end subroutine write_opening_history

    !> Per stage, the slab's placed sections along the slope: N, V, M, the fibre stresses and
    !> the crack-risk ratio (the full tables of every stage; the HDF5 file has the same).
    subroutine write_slab_history(unit, model, summaries)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        integer :: s, k
        if (.not. has_slab(model)) return
        write (unit, '(/,a,/,a,/,a)') repeat('-', 100), ' SLAB SECTIONS PER STAGE (per m '// &
            'of dam; S along the slab axis from its lowest element; N tension +; M + = '// &
            'tension on the water side; SIG: fibre stresses N/h +- 6M/h^2, kPa; RATIO: the '// &
            'larger fibre stress / f_t, blank without FT)', repeat('-', 100)
        write (unit, '(a)') '  STAGE DATE       WATER (m)  SECT      S (m)      Y (m)'// &
            '   N (kN/m)   V (kN/m)  M (kNm/m)  SIG WATER SIG CUSHION    RATIO'
        do s = 1, size(summaries)
            associate (sl => summaries(s)%slab)
                if (.not. allocated(sl%section_s)) cycle
                do k = 1, size(sl%section_s)
                    if (.not. sl%section_active(k)) cycle
                    write (unit, '(i7,1x,a10,a10,i6,2f11.3,5es11.3,a9)') s, &
                        date_of(summaries(s)), level_of(summaries(s)), k, sl%section_s(k), &
                        sl%section_y(k), sl%axial(k), sl%shear(k), sl%moment(k), &
                        sl%sigma_water(k), sl%sigma_cushion(k), ratio_text(sl, k)
                end do
            end associate
        end do
    end subroutine write_slab_history

    !> The crack-risk ratio of section k in 9 columns, blank without f_t.
    function ratio_text(sl, k) result(text)
        type(slab_result_t), intent(in) :: sl
        integer, intent(in) :: k
        character(len=9) :: text
        text = ''
        if (sl%tensile_strength(k) > 0.0_dp) write (text, '(f9.3)') sl%crack_ratio(k)
    end function ratio_text

    !> The largest opening width and depth of each slab phase over all stages, for the
    !> terminal summary (the paper's Table 5 quantities).
    subroutine write_opening_summary(unit, model, summaries)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        integer :: s, k, j, nphase
        integer, allocatable :: lines(:), groups(:), s_width(:), s_depth(:)
        real(dp), allocatable :: width(:), depth(:)
        if (.not. has_openings(model)) return
        allocate (lines(0), groups(0), s_width(0), s_depth(0), width(0), depth(0))
        do s = 1, size(summaries)
            do k = 1, size(summaries(s)%openings)
                associate (op => summaries(s)%openings(k))
                    j = 0
                    do nphase = 1, size(lines)
                        if (lines(nphase) == op%line .and. groups(nphase) == op%group) j = nphase
                    end do
                    if (j == 0) then
                        lines = [lines, op%line]
                        groups = [groups, op%group]
                        width = [width, -1.0_dp]
                        depth = [depth, -1.0_dp]
                        s_width = [s_width, 0]
                        s_depth = [s_depth, 0]
                        j = size(lines)
                    end if
                    if (op%width > width(j)) then
                        width(j) = op%width
                        s_width(j) = s
                    end if
                    if (op%depth > depth(j)) then
                        depth(j) = op%depth
                        s_depth(j) = s
                    end if
                end associate
            end do
        end do
        write (unit, '(a)') '  '//trim(merge('contact  ', 'interface', has_contact(model)))// &
            ' openings, largest over the stages (width m at stage / date; depth m at '// &
            'stage / date)'
        do j = 1, size(lines)
            write (unit, '(4x,a24,f9.4,i6,1x,a10,f9.3,i6,1x,a10)') &
                phase_name(model, opening_t(line=lines(j), group=groups(j))), width(j), &
                s_width(j), date_of(summaries(s_width(j))), depth(j), s_depth(j), &
                date_of(summaries(s_depth(j)))
        end do
    end subroutine write_opening_summary

    !> The interface stations and the slab sections of one stage.
    subroutine write_interface_tables(unit, model, stage)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(stage_result_t), intent(in) :: stage
        integer :: k, j
        if (has_interfaces(model)) then
            write (unit, '(/,a,/,a)') ' INTERFACE (n from the cushion to the slab; SIGN: '// &
                'normal stress, tension +; DUN: opening +; DUS: slip along the line)', &
                '   ELEM LINE TYPE  PT          X (m)          Y (m)          S (m)'// &
                '    SIGN (kPa)     TAU (kPa)       DUN (m)       DUS (m)'
            do k = 1, size(model%interfaces)
                if (.not. stage%interface%active(k)) cycle
                do j = 1, 2
                    write (unit, '(i7,i5,1x,a5,i4,3f15.4,4es14.5)') &
                        model%interfaces(k)%element, model%interfaces(k)%line, &
                        method_name(model%interfaces(k)%method), j, &
                        stage%interface%x(j, k), stage%interface%y(j, k), &
                        stage%interface%s(j, k), stage%interface%sigma_n(j, k), &
                        stage%interface%tau(j, k), stage%interface%du_n(j, k), &
                        stage%interface%du_s(j, k)
                end do
            end do
        end if
        if (has_contact(model)) then
            write (unit, '(/,a,/,a)') ' CONTACT (slave nodes; S along the slave surface; '// &
                'GAP + open; SLIP along t, accumulated; SIGN: normal traction, tension +; '// &
                'TAU: shear on the slave along t)', &
                '   NODE PAIR STATUS         X (m)          Y (m)          S (m)'// &
                '       GAP (m)      SLIP (m)    SIGN (kPa)     TAU (kPa)'
            associate (c => stage%contact)
                do k = 1, size(c%node)
                    if (.not. c%placed(k)) cycle
                    write (unit, '(i7,i5,1x,a6,3f15.4,4es14.5)') c%node(k), c%pair(k), &
                        status_names(c%status(k)), c%x(k), c%y(k), c%s(k), c%gap(k), &
                        c%slip(k), c%sigma_n(k), c%tau(k)
                end do
            end associate
        end if
        if (has_slab(model)) then
            write (unit, '(/,a,/,a,/,a)') ' SLAB SECTIONS (per m of dam; along the slab axis '// &
                'S from its lowest element; N tension +; M + = tension on the water side; '// &
                'RATIO: the larger fibre stress / f_t)', &
                '   SECT          S (m)          X (m)          Y (m)      H (m)'// &
                '     N (kN/m)     V (kN/m)   M (kNm/m) SIG WATER (kPa) SIG CUSHION (kPa)'// &
                '    RATIO'
            do k = 1, size(stage%slab%section_s)
                if (.not. stage%slab%section_active(k)) cycle
                write (unit, '(i7,3f15.4,f11.4,3es13.4,2es16.5,a9)') k, &
                    stage%slab%section_s(k), stage%slab%section_x(k), stage%slab%section_y(k), &
                    stage%slab%thickness(k), stage%slab%axial(k), stage%slab%shear(k), &
                    stage%slab%moment(k), stage%slab%sigma_water(k), &
                    stage%slab%sigma_cushion(k), ratio_text(stage%slab, k)
            end do
        end if
    end subroutine write_interface_tables

    !> Open DECK-interface.csv and DECK-slab.csv at `stem` (each only when the deck has
    !> interfaces or a slab) and write their headers, after a comment line with the
    !> `run_id` when given; `suffix` is appended to each name (e.g. '.part'). On an error
    !> the files opened so far are closed.
    subroutine open_interface_csv(csv, stem, suffix, model, error, run_id)
        type(interface_csv_t), intent(out) :: csv
        character(len=*), intent(in) :: stem, suffix
        type(model_t), intent(in) :: model
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: run_id
        if (has_interfaces(model)) then
            csv%interface_path = stem//'-interface.csv'//suffix
            call open_csv(csv%interface_path, 'stage,label,date,water_level_m,element,line,'// &
                          'type,group,point,x_m,y_m,s_m,sigma_n_kPa,tau_kPa,du_n_m,du_s_m', &
                          csv%interface_unit, error, run_id)
        end if
        if (has_contact(model) .and. .not. allocated(error)) then
            csv%contact_path = stem//'-contact.csv'//suffix
            call open_csv(csv%contact_path, 'stage,label,date,water_level_m,pair,node,group,'// &
                          'x_m,y_m,s_m,status,gap_m,slip_m,sigma_n_kPa,tau_kPa', &
                          csv%contact_unit, error, run_id)
        end if
        if (has_slab(model) .and. .not. allocated(error)) then
            csv%slab_path = stem//'-slab.csv'//suffix
            call open_csv(csv%slab_path, 'stage,label,date,water_level_m,section,s_m,x_m,'// &
                          'y_m,thickness_m,N_kN_per_m,V_kN_per_m,M_kNm_per_m,'// &
                          'sigma_water_side_kPa,sigma_cushion_side_kPa,crack_ratio', &
                          csv%slab_unit, error, run_id)
        end if
        if (allocated(error)) call close_interface_csv(csv)
    end subroutine open_interface_csv

    !> Open `path` for writing and write its header line, after the run id's comment line
    !> when `run_id` is given (unit 0 on failure).
    subroutine open_csv(path, header, unit, error, run_id)
        character(len=*), intent(in) :: path, header
        integer, intent(out) :: unit
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: run_id
        integer :: stat
        character(len=256) :: msg
        open (newunit=unit, file=path, status='replace', action='write', iostat=stat, &
              iomsg=msg)
        if (stat == 0 .and. present(run_id)) &
            write (unit, '(a)', iostat=stat, iomsg=msg) run_id_comment(run_id)
        if (stat == 0) write (unit, '(a)', iostat=stat, iomsg=msg) header
        if (stat /= 0) then
            call fatal_error(error, 'cannot write '//path//': '//trim(msg), io_error)
            close (unit, iostat=stat)
            unit = 0
        end if
    end subroutine open_csv

    !> The rows of stage `s`: its active interface stations and slab sections.
    subroutine append_interface_csv(csv, model, s, st, error)
        type(interface_csv_t), intent(in) :: csv
        type(model_t), intent(in) :: model
        integer, intent(in) :: s
        type(stage_result_t), intent(in) :: st
        type(error_t), allocatable, intent(out) :: error
        integer :: stat, k, j
        character(len=256) :: msg
        stat = 0
        if (csv%interface_unit /= 0) then
            do k = 1, size(model%interfaces)
                if (.not. st%interface%active(k)) cycle
                do j = 1, 2
                    write (csv%interface_unit, '(a)', iostat=stat, iomsg=msg) &
                        stage_columns(st, s)//','//to_text(model%interfaces(k)%element)// &
                        ','//to_text(model%interfaces(k)%line)//','// &
                        method_name(model%interfaces(k)%method)//','// &
                        group_text(model, model%mesh%group(model%interfaces(k)%element))// &
                        ','//to_text(j)//','//csv_real(st%interface%x(j, k))//','// &
                        csv_real(st%interface%y(j, k))//','// &
                        csv_real(st%interface%s(j, k))//','// &
                        csv_real(st%interface%sigma_n(j, k))//','// &
                        csv_real(st%interface%tau(j, k))//','// &
                        csv_real(st%interface%du_n(j, k))//','// &
                        csv_real(st%interface%du_s(j, k))
                    if (stat /= 0) then
                        call fatal_error(error, 'cannot write '//csv%interface_path//': '// &
                                         trim(msg), io_error)
                        return
                    end if
                end do
            end do
        end if
        if (csv%contact_unit /= 0) then
            associate (c => st%contact)
                do k = 1, size(c%node)
                    if (.not. c%placed(k)) cycle
                    write (csv%contact_unit, '(a)', iostat=stat, iomsg=msg) &
                        stage_columns(st, s)//','//to_text(c%pair(k))//','// &
                        to_text(c%node(k))//','//group_text(model, c%group(k))//','// &
                        csv_real(c%x(k))//','//csv_real(c%y(k))//','//csv_real(c%s(k))// &
                        ','//trim(status_names(c%status(k)))//','//csv_real(c%gap(k))//','// &
                        csv_real(c%slip(k))//','//csv_real(c%sigma_n(k))//','// &
                        csv_real(c%tau(k))
                    if (stat /= 0) then
                        call fatal_error(error, 'cannot write '//csv%contact_path//': '// &
                                         trim(msg), io_error)
                        return
                    end if
                end do
            end associate
        end if
        if (csv%slab_unit /= 0) then
            associate (sl => st%slab)
                do k = 1, size(sl%section_s)
                    if (.not. sl%section_active(k)) cycle
                    write (csv%slab_unit, '(a)', iostat=stat, iomsg=msg) stage_columns(st, s)// &
                        ','//to_text(k)//','//csv_real(sl%section_s(k))//','// &
                        csv_real(sl%section_x(k))//','//csv_real(sl%section_y(k))//','// &
                        csv_real(sl%thickness(k))//','//csv_real(sl%axial(k))//','// &
                        csv_real(sl%shear(k))//','//csv_real(sl%moment(k))//','// &
                        csv_real(sl%sigma_water(k))//','//csv_real(sl%sigma_cushion(k))// &
                        ','//csv_real(sl%crack_ratio(k))
                    if (stat /= 0) then
                        call fatal_error(error, 'cannot write '//csv%slab_path//': '// &
                                         trim(msg), io_error)
                        return
                    end if
                end do
            end associate
        end if
    end subroutine append_interface_csv

    !> Close the files (safe to call twice, or on files never opened).
    subroutine close_interface_csv(csv, error)
        type(interface_csv_t), intent(inout) :: csv
        type(error_t), allocatable, intent(out), optional :: error
        type(error_t), allocatable :: first
        call close_csv(csv%interface_unit, csv%interface_path, first)
        call close_csv(csv%contact_unit, csv%contact_path, first)
        call close_csv(csv%slab_unit, csv%slab_path, first)
        if (present(error) .and. allocated(first)) call move_alloc(first, error)
    end subroutine close_interface_csv

    !> Close `unit` if open (and set it to 0); the first failure is kept in `error`.
    subroutine close_csv(unit, path, error)
        integer, intent(inout) :: unit
        character(len=:), allocatable, intent(in) :: path
        type(error_t), allocatable, intent(inout) :: error
        integer :: stat
        character(len=256) :: msg
        if (unit == 0) return
        close (unit, iostat=stat, iomsg=msg)
        unit = 0
        if (stat /= 0 .and. .not. allocated(error)) &
            call fatal_error(error, 'cannot write '//path//': '//trim(msg), io_error)
    end subroutine close_csv

    !> DECK-openings.csv at `path` (decks with interfaces or contact): width, depth, length,
    !> top point and extreme normal stresses per slab phase and stage (line: the interface
    !> line, or the contact pair); a first comment line with the `run_id` when given.
    subroutine write_openings_csv(path, model, summaries, error, run_id)
        character(len=*), intent(in) :: path
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: run_id
        integer :: unit, stat, s, k
        character(len=256) :: msg
        open (newunit=unit, file=path, status='replace', action='write', iostat=stat, &
              iomsg=msg)
        if (stat /= 0) then
            call fatal_error(error, 'cannot write '//path//': '//trim(msg), io_error)
            return
        end if
        if (present(run_id)) write (unit, '(a)') run_id_comment(run_id)
        write (unit, '(a)') 'stage,label,date,water_level_m,line,group,width_m,depth_m,'// &
            'length_m,top_x_m,top_y_m,min_sigma_n_kPa,max_sigma_n_kPa,max_gap_m'
        do s = 1, size(summaries)
            associate (st => summaries(s))
                do k = 1, size(st%openings)
                    associate (op => st%openings(k))
                        write (unit, '(a)', iostat=stat, iomsg=msg) &
                            summary_columns(st, s)//','//to_text(op%line)//','// &
                            group_text(model, op%group)//','//csv_real(op%width)//','// &
                            csv_real(op%depth)//','//csv_real(op%length)//','// &
                            csv_real(op%top(1))//','//csv_real(op%top(2))//','// &
                            csv_real(op%max_compression)//','//csv_real(op%max_tension)// &
                            ','//csv_real(op%max_gap)
                    end associate
                    if (stat /= 0) exit
                end do
            end associate
            if (stat /= 0) exit
        end do
        close (unit)
        if (stat /= 0) call fatal_error(error, 'cannot write '//path//': '//trim(msg), io_error)
    end subroutine write_openings_csv

    !> stage,"label",date,water_level columns of a CSV row.
    function stage_columns(st, s) result(text)
        type(stage_result_t), intent(in) :: st
        integer, intent(in) :: s
        character(len=:), allocatable :: text
        text = to_text(s)//',"'//st%name//'",'//trim(adjustl(date_of(st)))//','
        if (st%water_level /= dry_level) text = text//trim(adjustl(level_of(st)))
    end function stage_columns

    !> The same columns from a stage's summary.
    function summary_columns(st, s) result(text)
        type(stage_summary_t), intent(in) :: st
        integer, intent(in) :: s
        character(len=:), allocatable :: text
        text = to_text(s)//',"'//st%name//'",'//trim(adjustl(date_of(st)))//','
        if (st%water_level /= dry_level) text = text//trim(adjustl(level_of(st)))
    end function summary_columns

    function group_text(model, group) result(text)
        type(model_t), intent(in) :: model
        integer, intent(in) :: group
        character(len=:), allocatable :: text
        text = ''
        if (group > 0) text = trim(model%mesh%group_name(group))
    end function group_text
end module cfrd_interface_io
