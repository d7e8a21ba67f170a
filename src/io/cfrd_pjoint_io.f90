!> The perimetric joints' results (PJOINT lines, docs/results.md): per stage the opening,
!> settlement and shear of each line as a listing table, as DECK-pjoint.csv and in the
!> HDF5 stage groups (/stages/NNNN/pjoint). Writers format; the values come from
!> analysis/cfrd_pjoint_results through the stage results and summaries.
module cfrd_pjoint_io
    use hdf5, only: hid_t
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, io_error
    use cfrd_model, only: model_t, law_pjoint
    use cfrd_results, only: stage_result_t
    use cfrd_stage_summary, only: stage_summary_t
    use cfrd_columns, only: csv_real, date_of, level_of, run_id_comment
    use cfrd_h5_datasets, only: h5_state_t, open_group, close_group, dataset_int1, &
                                dataset_real1
    implicit none
    private

    public :: has_pjoint, write_pjoint_table, write_pjoint_csv, write_pjoint_h5

contains

    !> The deck has an INTERFACE line of PJOINT material (a perimetric joint).
    pure logical function has_pjoint(model)
        type(model_t), intent(in) :: model
        integer :: k
        has_pjoint = .false.
        if (.not. allocated(model%interfaces)) return
        do k = 1, size(model%interfaces)
            associate (e => model%interfaces(k)%element)
                has_pjoint = has_pjoint .or. &
                    model%materials(model%mesh%material(e))%law == law_pjoint
            end associate
        end do
    end function has_pjoint

    !> Per stage and PJOINT line, once placed: opening, settlement and shear (mm) and the
    !> mean tractions (kPa).
    subroutine write_pjoint_table(unit, model, summaries)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        integer :: s, j
        if (.not. has_pjoint(model)) return
        write (unit, '(/,a)') ' PERIMETRIC JOINT (PJOINT lines; slab over plinth since '// &
            'placement, means over the line: OPENING along n, SETTLEMENT along t, SHEAR out '// &
            'of plane)'
        write (unit, '(a)') '  STAGE DATE       WATER (m)  LINE OPENING (mm) SETTLEMENT (mm)'// &
            '  SHEAR (mm)  SIGMA_N (kPa)   TAU (kPa)'
        do s = 1, size(summaries)
            associate (p => summaries(s)%pjoint)
                if (.not. allocated(p%line)) cycle
                do j = 1, size(p%line)
                    if (.not. p%active(j)) cycle
                    write (unit, '(i7,1x,a10,a10,i6,f13.3,f16.3,f12.3,2f14.2)') s, &
                        date_of(summaries(s)), level_of(summaries(s)), p%line(j), &
                        1.0e3_dp*p%opening(j) + 0.0_dp, 1.0e3_dp*p%settlement(j) + 0.0_dp, &
                        1.0e3_dp*p%shear(j) + 0.0_dp, p%sigma_n(j) + 0.0_dp, p%tau(j) + 0.0_dp
                end do
            end associate
        end do
    end subroutine write_pjoint_table

    !> DECK-pjoint.csv: one row per stage and PJOINT line (docs/results.md); a first
    !> comment line gives the run id.
    subroutine write_pjoint_csv(path, model, summaries, error, run_id)
        character(len=*), intent(in) :: path
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: run_id
        integer :: unit, stat, s, j
        character(len=256) :: msg
        character(len=16) :: number
        if (.not. has_pjoint(model)) return
        open (newunit=unit, file=path, status='replace', action='write', iostat=stat, &
              iomsg=msg)
        if (stat /= 0) then
            call fatal_error(error, 'cannot write the perimetric joint histories '//path// &
                             ': '//trim(msg), io_error)
            return
        end if
        if (present(run_id)) write (unit, '(a)') run_id_comment(run_id)
        write (unit, '(a)') 'stage,label,date,water_level_m,line,active,opening_m,'// &
            'settlement_m,shear_m,sigma_n_kpa,tau_kpa'
        do s = 1, size(summaries)
            associate (st => summaries(s), p => summaries(s)%pjoint)
                if (.not. allocated(p%line)) cycle
                do j = 1, size(p%line)
                    write (number, '(i0)') p%line(j)
                    write (unit, '(i0,a)', iostat=stat, iomsg=msg) s, ',"'//st%name//'",'// &
                        trim(adjustl(date_of(st)))//','//trim(adjustl(level_text(st)))// &
                        ','//trim(number)//','//merge('1', '0', p%active(j))//','// &
                        csv_real(p%opening(j))//','//csv_real(p%settlement(j))//','// &
                        csv_real(p%shear(j))//','//csv_real(p%sigma_n(j))//','// &
                        csv_real(p%tau(j))
                end do
            end associate
        end do
        close (unit)
        if (stat /= 0) call fatal_error(error, 'cannot write the perimetric joint '// &
                                        'histories '//path//': '//trim(msg), io_error)
    contains
        !> The level as the gauge CSV has it: blank before the first WATER stage.
        function level_text(st) result(text)
            type(stage_summary_t), intent(in) :: st
            character(len=:), allocatable :: text
            text = level_of(st)
            if (adjustl(text) == 'empty') text = ''
        end function level_text
    end subroutine write_pjoint_csv

    !> The stage's perimetric joints as the group `pjoint` of the stage group.
    subroutine write_pjoint_h5(stage_id, stage, st)
        integer(hid_t), intent(in) :: stage_id
        type(stage_result_t), intent(in) :: stage
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: id
        if (.not. allocated(stage%pjoint%line)) return
        if (size(stage%pjoint%line) == 0) return
        call open_group(stage_id, 'pjoint', id, st)
        associate (p => stage%pjoint)
            call dataset_int1(id, 'line', p%line, st)
            call dataset_int1(id, 'active', merge(1, 0, p%active), st)
            call dataset_real1(id, 'opening', p%opening, 'm', &
                               'slab over plinth along n, mean over the line, open +', st)
            call dataset_real1(id, 'settlement', p%settlement, 'm', &
                               'slab over plinth along t (normal to the face), mean', st)
            call dataset_real1(id, 'shear', p%shear, 'm', &
                               'along the joint, out of the plane: 0 in plane strain', st)
            call dataset_real1(id, 'sigma_n', p%sigma_n, 'kPa', 'mean, tension +', st)
            call dataset_real1(id, 'tau', p%tau, 'kPa', 'mean, along t', st)
        end associate
        call close_group(id, st)
    end subroutine write_pjoint_h5
end module cfrd_pjoint_io
