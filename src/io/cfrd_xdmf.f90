!> The XDMF file beside a results file (DECK.xmf beside DECK.h5), so that ParaView (and
!> readers such as meshio) open the results as a time series: one temporal collection, one
!> grid per completed stage at time = the stage number, each a Quadrilateral topology over
!> the mesh, with node attributes displacement and displacement_total (three components,
!> z = 0) and cell attributes stress_centroid, principal (files written with --results
!> full only), stress_level, active, material and group. The XML holds no numbers of its own:
!> every DataItem points into the HDF5 file by a path relative to the XDMF file
!> (docs/results.md). A lean file (the default) has no three-component copies nor
!> displacement_total: the vectors are XDMF Functions, JOIN($0, $1, 0 * $0) of the two
!> columns of the (nnode, 2) displacement taken as HyperSlabs, plus for displacement_total
!> the columns of u_before_reset of the last RESET stage (each a Function $0 + $1), and
!> (double-precision files) stress_centroid, a Function of the four Gauss points of
!> stress_gauss taken as HyperSlabs divided by /mesh/gauss_points (function centroid).
module cfrd_xdmf
    use cfrd_error, only: error_t, fatal_error, io_error
    use cfrd_model, only: model_t, stage_reset
    use cfrd_strings, only: to_text
    implicit none
    private

    public :: write_xdmf, xml_escape

contains

    !> Write the XDMF file `path` for the first `nstages` stages of the results file whose
    !> name, relative to the XDMF file, is `h5_name`; a comment gives the `run_id` of the
    !> result set when given.
    subroutine write_xdmf(path, h5_name, model, nstages, error, run_id, single, full)
        character(len=*), intent(in) :: path, h5_name
        type(model_t), intent(in) :: model
        integer, intent(in) :: nstages
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: run_id
        !> the stages' real datasets are in single precision (cfrd --float32)
        logical, intent(in), optional :: single
        !> the file has the derived fields and the three-component copies (--results full)
        logical, intent(in), optional :: full
        logical :: all_fields
        character(len=1) :: fp
        integer :: unit, stat, s, reset
        character(len=256) :: msg
        character(len=:), allocatable :: nnode, nelem, stage
        character(len=16) :: stage_name
        open (newunit=unit, file=path, status='replace', action='write', iostat=stat, &
              iomsg=msg)
        if (stat /= 0) then
            call fatal_error(error, 'cannot write the XDMF file '//path//': '//trim(msg), &
                             io_error)
            return
        end if
        fp = '8'
        if (present(single)) then
            if (single) fp = '4'
        end if
        all_fields = .false.
        if (present(full)) all_fields = full
        nnode = to_text(model%mesh%nnode)
        nelem = to_text(model%mesh%nelem)
        write (unit, '(a)', iostat=stat, iomsg=msg) '<?xml version="1.0" ?>', &
            '<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>'
        if (present(run_id) .and. stat == 0) &
            write (unit, '(a)', iostat=stat, iomsg=msg) '<!-- cfrd run_id '//run_id//' -->'
        if (stat == 0) write (unit, '(a)', iostat=stat, iomsg=msg) &
            '<Xdmf Version="3.0">', &
            '  <Domain>', &
            '    <Grid Name="'//xml_escape(model%title)//'" GridType="Collection" '// &
            'CollectionType="Temporal">'
        reset = 0
        do s = 1, nstages
            if (stat /= 0) exit
            if (model%stages(s)%kind == stage_reset) reset = s
            write (stage_name, '(a,i4.4)') 'stage_', s
            stage = '/stages/'//trim(stage_name)//'/'
            write (unit, '(a)', iostat=stat, iomsg=msg) &
                '      <Grid Name="'//trim(stage_name)//'" GridType="Uniform">', &
                '        <Information Name="label" Value="'// &
                xml_escape(model%stages(s)%label)//'"/>', &
                '        <Time Value="'//to_text(s)//'"/>', &
                '        <Topology TopologyType="Quadrilateral" NumberOfElements="'//nelem// &
                '">', &
                item(nelem//' 4', 'Int', '4', '/mesh/connectivity_zero_based'), &
                '        </Topology>', &
                '        <Geometry GeometryType="XY">', &
                item(nnode//' 2', 'Float', '8', '/mesh/coordinates'), &
                '        </Geometry>', &
                vector('displacement', stage//'displacement', ''), &
                vector('displacement_total', stage//'displacement', offset(reset))
            if (all_fields .and. stat == 0) write (unit, '(a)', iostat=stat, iomsg=msg) &
                attribute('stress_centroid', 'Matrix', 'Cell', nelem//' 4', 'Float', fp, &
                          stage//'stress_centroid'), &
                attribute('principal', 'Matrix', 'Cell', nelem//' 3', 'Float', fp, &
                          stage//'principal')
            if (.not. all_fields .and. fp == '8' .and. stat == 0) &
                write (unit, '(a)', iostat=stat, iomsg=msg) centroid(stage//'stress_gauss')
            if (stat == 0) write (unit, '(a)', iostat=stat, iomsg=msg) &
                attribute('stress_level', 'Scalar', 'Cell', nelem, 'Float', fp, &
                          stage//'stress_level'), &
                attribute('active', 'Scalar', 'Cell', nelem, 'Int', '4', stage//'active'), &
                attribute('material', 'Scalar', 'Cell', nelem, 'Int', '4', '/mesh/material'), &
                attribute('group', 'Scalar', 'Cell', nelem, 'Int', '4', '/mesh/group'), &
                '      </Grid>'
        end do
        if (stat == 0) write (unit, '(a)', iostat=stat, iomsg=msg) '    </Grid>', &
            '  </Domain>', '</Xdmf>'
        close (unit)
        if (stat /= 0) call fatal_error(error, 'cannot write the XDMF file '//path//': '// &
                                        trim(msg), io_error)
    contains
        function item(dims, number_type, precision, dataset) result(text)
            character(len=*), intent(in) :: dims, number_type, precision, dataset
            character(len=:), allocatable :: text
            text = '          <DataItem Dimensions="'//dims//'" DataType="'//number_type// &
                   '" Precision="'//precision//'" Format="HDF">'//xml_escape(h5_name)//':'// &
                   dataset//'</DataItem>'
        end function item

        !> The node vector `name` with z = 0: its copy padded with z = 0 (name_xyz, --results
        !> full), else the (nnode, 2) dataset `dataset` padded by XDMF (module comment), plus
        !> the (nnode, 2) dataset `shift` when one is named (a lean file's displacement_total:
        !> displacement + u_before_reset of the last RESET stage).
        function vector(name, dataset, shift) result(text)
            character(len=*), intent(in) :: name, dataset, shift
            character(len=:), allocatable :: text
            if (all_fields) then
                text = attribute(name, 'Vector', 'Node', nnode//' 3', 'Float', fp, &
                                 dataset(:index(dataset, '/', back=.true.))//name//'_xyz')
                return
            end if
            text = '        <Attribute Name="'//name//'" AttributeType="Vector" '// &
                   'Center="Node">'//new_line('a')
            if (len(shift) == 0) then
                text = text//'          <DataItem ItemType="Function" '// &
                       'Function="JOIN($0, $1, 0 * $0)" Dimensions="'//nnode//' 3">'// &
                       new_line('a')//column(dataset, '0')//column(dataset, '1')
            else
                ! (VTK's XDMF reader evaluates JOIN($0 + $2, ...) wrongly: nested sums)
                text = text//'          <DataItem ItemType="Function" '// &
                       'Function="JOIN($0, $1, 0 * $0)" Dimensions="'//nnode//' 3">'// &
                       new_line('a')//sum(dataset, shift, '0')//sum(dataset, shift, '1')
            end if
            text = text//'          </DataItem>'//new_line('a')//'        </Attribute>'
        end function vector

        !> A lean file's stress_centroid, (nelem, 4): the element's Gauss-point stresses
        !> of the (nelem, 4, 4) dataset summed from zero in Gauss-point order, divided by
        !> its Gauss-point count /mesh/gauss_points (the stage driver's
        !> sum(stress(:, 1:ng, e))/ng: a joint's unused slots hold zeros, which add nothing;
        !> the leading 0 + gives +0 where all four are -0, as the sum from zero does).
        function centroid(dataset) result(text)
            character(len=*), intent(in) :: dataset
            character(len=:), allocatable :: text
            integer :: k
            text = '        <Attribute Name="stress_centroid" AttributeType="Matrix" '// &
                   'Center="Cell">'//new_line('a')// &
                   '          <DataItem ItemType="Function" '// &
                   'Function="(0 + $0 + $1 + $2 + $3) / $4" Dimensions="'//nelem//' 4">'// &
                   new_line('a')
            do k = 0, 3
                text = text//'          <DataItem ItemType="HyperSlab" Dimensions="'// &
                       nelem//' 4" Type="HyperSlab">'//new_line('a')// &
                       '          <DataItem Dimensions="3 3" Format="XML">0 '// &
                       to_text(k)//' 0 1 1 1 '//nelem//' 1 4</DataItem>'//new_line('a')// &
                       item(nelem//' 4 4', 'Float', fp, dataset)//new_line('a')// &
                       '          </DataItem>'//new_line('a')
            end do
            text = text//item(nelem//' 4', 'Int', '4', '/mesh/gauss_points')// &
                   new_line('a')//'          </DataItem>'//new_line('a')//'        </Attribute>'
        end function centroid

        !> Column k of dataset + column k of shift, (nnode, 1).
        function sum(dataset, shift, k) result(item)
            character(len=*), intent(in) :: dataset, shift, k
            character(len=:), allocatable :: item
            item = '          <DataItem ItemType="Function" Function="$0 + $1" '// &
                   'Dimensions="'//nnode//' 1">'//new_line('a')//column(dataset, k)// &
                   column(shift, k)//'          </DataItem>'//new_line('a')
        end function sum

        !> The lean file's u_before_reset of stage k (none before the first RESET).
        function offset(k) result(path)
            integer, intent(in) :: k
            character(len=:), allocatable :: path
            character(len=16) :: name
            path = ''
            if (k == 0) return
            write (name, '(a,i4.4)') 'stage_', k
            path = '/stages/'//trim(name)//'/u_before_reset'
        end function offset

        !> column k (0-based) of the (nnode, 2) dataset, (nnode, 1)
        function column(dataset, k) result(slab)
            character(len=*), intent(in) :: dataset, k
            character(len=:), allocatable :: slab
            slab = '          <DataItem ItemType="HyperSlab" Dimensions="'//nnode// &
                   ' 1" Type="HyperSlab">'//new_line('a')// &
                   '          <DataItem Dimensions="3 2" Format="XML">0 '//k//' 1 1 '// &
                   nnode//' 1</DataItem>'//new_line('a')// &
                   item(nnode//' 2', 'Float', fp, dataset)//new_line('a')// &
                   '          </DataItem>'//new_line('a')
        end function column

        function attribute(name, kind, center, dims, number_type, precision, dataset) &
            result(text)
            character(len=*), intent(in) :: name, kind, center, dims, number_type, precision, &
                                            dataset
            character(len=:), allocatable :: text
            text = '        <Attribute Name="'//name//'" AttributeType="'//kind// &
                   '" Center="'//center//'">'//new_line('a')// &
                   item(dims, number_type, precision, dataset)//new_line('a')// &
                   '        </Attribute>'
        end function attribute
    end subroutine write_xdmf

    !> Text with XML's five special characters escaped, for attribute values and content.
    pure function xml_escape(text) result(escaped)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: escaped
        integer :: i
        escaped = ''
        do i = 1, len(text)
            select case (text(i:i))
            case ('&')
                escaped = escaped//'&amp;'
            case ('<')
                escaped = escaped//'&lt;'
            case ('>')
                escaped = escaped//'&gt;'
            case ('"')
                escaped = escaped//'&quot;'
            case ("'")
                escaped = escaped//'&apos;'
            case default
                escaped = escaped//text(i:i)
            end select
        end do
    end function xml_escape
end module cfrd_xdmf
