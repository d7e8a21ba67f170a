!> The HDF5 writing helpers of the results file (io/cfrd_hdf5): groups, datasets of reals
!> and integers (large ones chunked through shuffle + deflate, optionally in single
!> precision), texts and attributes. Every HDF5 status is checked; the first failure is
!> carried in `h5_state_t`, so that later calls are skipped and the caller reports it.
module cfrd_h5_datasets
    use hdf5, only: hid_t, hsize_t, h5gcreate_f, h5gclose_f, h5screate_simple_f, h5screate_f, &
                    h5sclose_f, h5dcreate_f, h5dwrite_f, h5dclose_f, h5acreate_f, &
                    h5awrite_f, h5aclose_f, h5aopen_f, h5aexists_f, h5tcopy_f, &
                    h5tset_size_f, h5tclose_f, H5S_SCALAR_F, H5T_NATIVE_DOUBLE, &
                    H5T_NATIVE_INTEGER, H5T_NATIVE_CHARACTER, h5pcreate_f, h5pclose_f, &
                    h5pset_chunk_f, h5pset_shuffle_f, h5pset_deflate_f, H5P_DATASET_CREATE_F, &
                    H5T_NATIVE_REAL
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: h5_state_t, fail, open_group, close_group, dataset_real1, dataset_real2, &
              dataset_real3, dataset_int1, dataset_int2, dataset_text, dataset_names, &
              attr_text, attr_real, attr_int, set_attr_int

    !> Datasets of at least min_filtered values are stored in chunks of at most
    !> chunk_values values through the shuffle and deflate filters (filtered_layout).
    integer(hsize_t), parameter :: min_filtered = 1024, chunk_values = 131072

    !> The first failure of a sequence of HDF5 calls.
    type :: h5_state_t
        logical :: ok = .true.
        character(len=:), allocatable :: failed   !! what was being written
        integer :: deflate = 0        !! the deflate level of large datasets (0: none)
        logical :: single = .false.   !! real datasets in single precision
    end type h5_state_t

contains

    subroutine fail(st, what)
        type(h5_state_t), intent(inout) :: st
        character(len=*), intent(in) :: what
        if (.not. st%ok) return
        st%ok = .false.
        st%failed = what
    end subroutine fail

    subroutine open_group(loc, name, group_id, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        integer(hid_t), intent(out) :: group_id
        type(h5_state_t), intent(inout) :: st
        integer :: hdferr
        group_id = -1
        if (.not. st%ok) return
        call h5gcreate_f(loc, name, group_id, hdferr)
        if (hdferr < 0) call fail(st, 'group '//name)
    end subroutine open_group

    subroutine close_group(group_id, st)
        integer(hid_t), intent(in) :: group_id
        type(h5_state_t), intent(inout) :: st
        integer :: hdferr
        if (group_id < 0) return
        call h5gclose_f(group_id, hdferr)
        if (hdferr < 0) call fail(st, 'closing a group')
    end subroutine close_group

    !> Create a dataset of `type_id` and shape `dims`; the caller writes and closes it.
    subroutine create_dataset(loc, name, type_id, dims, dset_id, st)
        integer(hid_t), intent(in) :: loc, type_id
        character(len=*), intent(in) :: name
        integer(hsize_t), intent(in) :: dims(:)
        integer(hid_t), intent(out) :: dset_id
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: space_id, plist_id
        integer :: hdferr
        dset_id = -1
        if (.not. st%ok) return
        if (size(dims) == 0) then
            call h5screate_f(H5S_SCALAR_F, space_id, hdferr)
        else
            call h5screate_simple_f(size(dims), dims, space_id, hdferr)
        end if
        if (hdferr < 0) then
            call fail(st, 'dataspace of '//name)
            return
        end if
        if (st%deflate > 0 .and. product(dims) >= min_filtered) then
            call filtered_layout(dims, st%deflate, plist_id, hdferr)
            if (hdferr < 0) then
                call fail(st, 'the chunked layout of '//name)
                call h5sclose_f(space_id, hdferr)
                return
            end if
            call h5dcreate_f(loc, name, type_id, space_id, dset_id, hdferr, dcpl_id=plist_id)
            if (hdferr < 0) call fail(st, 'dataset '//name)
            call h5pclose_f(plist_id, hdferr)
        else
            call h5dcreate_f(loc, name, type_id, space_id, dset_id, hdferr)
            if (hdferr < 0) call fail(st, 'dataset '//name)
        end if
        call h5sclose_f(space_id, hdferr)
    end subroutine create_dataset

    !> The creation properties of a large dataset: chunks of at most chunk_values values,
    !> each passed through the shuffle filter (the bytes of the values regrouped by
    !> significance) and deflate (zlib) at `level`. A chunk holds one component (the
    !> fastest-varying dimension: xx, yy, zz or xy; ux or uy) of a run of elements or nodes,
    !> whole along the dimensions between (the Gauss points), cut along the slowest: the
    !> values of one component share sign and exponent, which shuffle and deflate then find
    !> together (a lean x4 file 7 % smaller than with the components interleaved,
    !> docs/performance.md (q-files)). Both filters are HDF5's own, so h5py, ParaView and
    !> XDMF readers read the file without change, and lossless: the values read back are
    !> the values written (docs/results.md).
    subroutine filtered_layout(dims, level, plist_id, hdferr)
        integer(hsize_t), intent(in) :: dims(:)
        integer, intent(in) :: level
        integer(hid_t), intent(out) :: plist_id
        integer, intent(out) :: hdferr
        integer(hsize_t) :: chunk(size(dims)), inner
        integer :: k, err
        call h5pcreate_f(H5P_DATASET_CREATE_F, plist_id, hdferr)
        if (hdferr < 0) return
        chunk = dims
        k = size(dims)
        if (k >= 2) chunk(1) = 1
        inner = max(product(chunk(1:k - 1)), 1_hsize_t)
        chunk(k) = max(1_hsize_t, min(dims(k), chunk_values/inner))
        call h5pset_chunk_f(plist_id, size(dims), chunk, hdferr)
        if (hdferr >= 0) call h5pset_shuffle_f(plist_id, hdferr)
        if (hdferr >= 0) call h5pset_deflate_f(plist_id, level, hdferr)
        if (hdferr < 0) call h5pclose_f(plist_id, err)
    end subroutine filtered_layout

    subroutine finish_dataset(dset_id, name, hdferr, units, components, st)
        integer(hid_t), intent(in) :: dset_id
        character(len=*), intent(in) :: name
        integer, intent(in) :: hdferr
        character(len=*), intent(in), optional :: units, components
        type(h5_state_t), intent(inout) :: st
        integer :: close_err
        if (dset_id < 0) return
        if (hdferr < 0) call fail(st, 'writing dataset '//name)
        if (present(units)) call attr_text(dset_id, 'units', units, st)
        if (present(components)) call attr_text(dset_id, 'components', components, st)
        call h5dclose_f(dset_id, close_err)
        if (close_err < 0) call fail(st, 'closing dataset '//name)
    end subroutine finish_dataset

    subroutine dataset_real2(loc, name, values, units, components, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name, units, components
        real(dp), intent(in) :: values(:, :)
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: dset_id
        integer(hsize_t) :: dims(2)
        integer :: hdferr
        dims = shape(values, kind=hsize_t)
        call create_dataset(loc, name, merge(H5T_NATIVE_REAL, H5T_NATIVE_DOUBLE, st%single), &
                            dims, dset_id, st)
        if (dset_id < 0) return
        call h5dwrite_f(dset_id, H5T_NATIVE_DOUBLE, values, dims, hdferr)
        call finish_dataset(dset_id, name, hdferr, units, components, st)
    end subroutine dataset_real2

    subroutine dataset_real3(loc, name, values, units, components, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name, units, components
        real(dp), intent(in) :: values(:, :, :)
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: dset_id
        integer(hsize_t) :: dims(3)
        integer :: hdferr
        dims = shape(values, kind=hsize_t)
        call create_dataset(loc, name, merge(H5T_NATIVE_REAL, H5T_NATIVE_DOUBLE, st%single), &
                            dims, dset_id, st)
        if (dset_id < 0) return
        call h5dwrite_f(dset_id, H5T_NATIVE_DOUBLE, values, dims, hdferr)
        call finish_dataset(dset_id, name, hdferr, units, components, st)
    end subroutine dataset_real3

    subroutine dataset_real1(loc, name, values, units, components, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name, units, components
        real(dp), intent(in) :: values(:)
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: dset_id
        integer(hsize_t) :: dims(1)
        integer :: hdferr
        dims = shape(values, kind=hsize_t)
        call create_dataset(loc, name, merge(H5T_NATIVE_REAL, H5T_NATIVE_DOUBLE, st%single), &
                            dims, dset_id, st)
        if (dset_id < 0) return
        call h5dwrite_f(dset_id, H5T_NATIVE_DOUBLE, values, dims, hdferr)
        call finish_dataset(dset_id, name, hdferr, units, components, st)
    end subroutine dataset_real1

    subroutine dataset_int1(loc, name, values, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        integer, intent(in) :: values(:)
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: dset_id
        integer(hsize_t) :: dims(1)
        integer :: hdferr
        dims = shape(values, kind=hsize_t)
        call create_dataset(loc, name, H5T_NATIVE_INTEGER, dims, dset_id, st)
        if (dset_id < 0) return
        call h5dwrite_f(dset_id, H5T_NATIVE_INTEGER, values, dims, hdferr)
        call finish_dataset(dset_id, name, hdferr, st=st)
    end subroutine dataset_int1

    subroutine dataset_int2(loc, name, values, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        integer, intent(in) :: values(:, :)
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: dset_id
        integer(hsize_t) :: dims(2)
        integer :: hdferr
        dims = shape(values, kind=hsize_t)
        call create_dataset(loc, name, H5T_NATIVE_INTEGER, dims, dset_id, st)
        if (dset_id < 0) return
        call h5dwrite_f(dset_id, H5T_NATIVE_INTEGER, values, dims, hdferr)
        call finish_dataset(dset_id, name, hdferr, st=st)
    end subroutine dataset_int2

    !> A fixed-length string type of `length` characters (at least 1).
    subroutine string_type(length, type_id, st)
        integer, intent(in) :: length
        integer(hid_t), intent(out) :: type_id
        type(h5_state_t), intent(inout) :: st
        integer :: hdferr
        call h5tcopy_f(H5T_NATIVE_CHARACTER, type_id, hdferr)
        if (hdferr >= 0) call h5tset_size_f(type_id, int(max(length, 1), hsize_t), hdferr)
        if (hdferr < 0) call fail(st, 'string type')
    end subroutine string_type

    subroutine dataset_text(loc, name, text, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name, text
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: dset_id, type_id
        integer(hsize_t) :: dims(0)
        integer :: hdferr
        if (.not. st%ok) return
        call string_type(len(text), type_id, st)
        call create_dataset(loc, name, type_id, dims, dset_id, st)
        if (dset_id >= 0) then
            if (len(text) > 0) then
                call h5dwrite_f(dset_id, type_id, text, dims, hdferr)
            else
                call h5dwrite_f(dset_id, type_id, ' ', dims, hdferr)
            end if
            call finish_dataset(dset_id, name, hdferr, st=st)
        end if
        call h5tclose_f(type_id, hdferr)
    end subroutine dataset_text

    subroutine dataset_names(loc, name, names, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name, names(:)
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: dset_id, type_id
        integer(hsize_t) :: dims(1)
        integer :: hdferr
        if (.not. st%ok) return
        dims = size(names, kind=hsize_t)
        call string_type(len(names), type_id, st)
        call create_dataset(loc, name, type_id, dims, dset_id, st)
        if (dset_id >= 0) then
            call h5dwrite_f(dset_id, type_id, names, dims, hdferr)
            call finish_dataset(dset_id, name, hdferr, st=st)
        end if
        call h5tclose_f(type_id, hdferr)
    end subroutine dataset_names

    subroutine attr_text(loc, name, text, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name, text
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: space_id, type_id, attr_id
        integer(hsize_t) :: dims(1) = 1
        integer :: hdferr
        if (.not. st%ok) return
        call string_type(len(text), type_id, st)
        call h5screate_f(H5S_SCALAR_F, space_id, hdferr)
        call h5acreate_f(loc, name, type_id, space_id, attr_id, hdferr)
        if (hdferr >= 0) then
            if (len(text) > 0) then
                call h5awrite_f(attr_id, type_id, text, dims, hdferr)
            else
                call h5awrite_f(attr_id, type_id, ' ', dims, hdferr)
            end if
            if (hdferr < 0) call fail(st, 'attribute '//name)
            call h5aclose_f(attr_id, hdferr)
        else
            call fail(st, 'attribute '//name)
        end if
        call h5sclose_f(space_id, hdferr)
        call h5tclose_f(type_id, hdferr)
    end subroutine attr_text

    subroutine attr_real(loc, name, values, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        real(dp), intent(in) :: values(:)
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: space_id, attr_id
        integer(hsize_t) :: dims(1)
        integer :: hdferr
        if (.not. st%ok) return
        dims = size(values, kind=hsize_t)
        ! One value is a scalar attribute (h5py reads a float, not an array).
        if (size(values) == 1) then
            call h5screate_f(H5S_SCALAR_F, space_id, hdferr)
        else
            call h5screate_simple_f(1, dims, space_id, hdferr)
        end if
        call h5acreate_f(loc, name, H5T_NATIVE_DOUBLE, space_id, attr_id, hdferr)
        if (hdferr >= 0) then
            call h5awrite_f(attr_id, H5T_NATIVE_DOUBLE, values, dims, hdferr)
            if (hdferr < 0) call fail(st, 'attribute '//name)
            call h5aclose_f(attr_id, hdferr)
        else
            call fail(st, 'attribute '//name)
        end if
        call h5sclose_f(space_id, hdferr)
    end subroutine attr_real

    subroutine attr_int(loc, name, value, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        integer, intent(in) :: value
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: space_id, attr_id
        integer(hsize_t) :: dims(1) = 1
        integer :: hdferr
        if (.not. st%ok) return
        call h5screate_f(H5S_SCALAR_F, space_id, hdferr)
        call h5acreate_f(loc, name, H5T_NATIVE_INTEGER, space_id, attr_id, hdferr)
        if (hdferr >= 0) then
            call h5awrite_f(attr_id, H5T_NATIVE_INTEGER, [value], dims, hdferr)
            if (hdferr < 0) call fail(st, 'attribute '//name)
            call h5aclose_f(attr_id, hdferr)
        else
            call fail(st, 'attribute '//name)
        end if
        call h5sclose_f(space_id, hdferr)
    end subroutine attr_int

    !> Set an integer attribute, creating it if it does not exist.
    subroutine set_attr_int(loc, name, value, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        integer, intent(in) :: value
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: attr_id
        integer(hsize_t) :: dims(1) = 1
        integer :: hdferr
        logical :: exists
        if (.not. st%ok) return
        call h5aexists_f(loc, name, exists, hdferr)
        if (hdferr < 0) then
            call fail(st, 'attribute '//name)
            return
        end if
        if (.not. exists) then
            call attr_int(loc, name, value, st)
            return
        end if
        call h5aopen_f(loc, name, attr_id, hdferr)
        if (hdferr < 0) then
            call fail(st, 'attribute '//name)
            return
        end if
        call h5awrite_f(attr_id, H5T_NATIVE_INTEGER, [value], dims, hdferr)
        if (hdferr < 0) call fail(st, 'attribute '//name)
        call h5aclose_f(attr_id, hdferr)
    end subroutine set_attr_int
end module cfrd_h5_datasets
