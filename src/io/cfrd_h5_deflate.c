/* HDF5's deflate filter (id H5Z_FILTER_DEFLATE = 1) computed by libdeflate instead of zlib,
 * in cfrd's process only (issue 21; docs/performance.md (u)).
 *
 * The files stay standard: the datasets keep filter id 1, its one client value (the level,
 * 0-9) and its name "deflate", and every chunk is a zlib stream (RFC 1950), which any HDF5
 * reader (h5py, ParaView, h5dump) inflates with zlib as before. Only the compressed bytes
 * differ from zlib's (another encoder of the same format); the values read back are the
 * same bits. libdeflate compresses whole buffers, which is what an HDF5 chunk is, about
 * twice as fast as zlib at level 1 (docs/performance.md (r)).
 *
 * The filter function follows HDF5's own (H5Zdeflate.c, 1.10): compressing, an output
 * buffer of the worst case (libdeflate's bound), *buf_size the input's size, the compressed
 * size returned; decompressing, an output buffer grown by doubling until the stream fits
 * (its size is not stored in the file), *buf_size the buffer's size, the decompressed size
 * returned; 0 on any failure. H5Pset_deflate marks the filter optional (H5Z_FLAG_OPTIONAL),
 * so a chunk whose compression fails is stored unfiltered, as with HDF5's own filter, and
 * read back as such; a read that fails is an HDF5 read error, as with zlib.
 *
 * Registration: the public H5Zregister refuses the predefined ids (below
 * H5Z_FILTER_RESERVED); H5Z_register, the library's internal function it calls after that
 * check, replaces the class of an id already in the table. It is an exported symbol of
 * libhdf5 (the static archive and the shared library, 1.8 to 1.14) with the same signature.
 * H5close empties the table and the next H5open puts zlib's filter back, so cfrd registers
 * after every H5open (cfrd_h5_deflate.f90, h5_open).
 *
 * One compressor per level and one decompressor are kept for the process (freed at exit):
 * HDF5 calls its filters from one thread at a time: the thread-safe library (Debian's) runs
 * one API call at a time, and cfrd's stage writer (cfrd_stage_writer) writes on a second
 * thread while the analysis may read a restart file.
 */
#include <stddef.h>
#include <stdlib.h>

#include <libdeflate.h>

#if defined(__has_include)
#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>   /* Debian's serial HDF5, outside the default include path */
#endif
#else
#include <hdf5.h>
#endif

/* HDF5's internal registration (H5Zprivate.h), which allows the predefined ids. */
extern herr_t H5Z_register(const H5Z_class2_t *cls);

#define MAX_LEVEL 12   /* libdeflate's levels 0-12; HDF5's deflate levels 0-9 map to the same */

static struct libdeflate_compressor *compressors[MAX_LEVEL + 1];
static struct libdeflate_decompressor *decompressor;
static size_t last_inflated;      /* size of the last chunk decompressed: the first guess */
static long count_deflated, count_inflated, count_failed;
static int exit_hook;

static void free_coders(void)
{
    for (int k = 0; k <= MAX_LEVEL; k++) {
        libdeflate_free_compressor(compressors[k]);
        compressors[k] = NULL;
    }
    libdeflate_free_decompressor(decompressor);
    decompressor = NULL;
}

static size_t deflate_chunk(unsigned level, size_t nbytes, size_t *buf_size, void **buf)
{
    if (compressors[level] == NULL) compressors[level] = libdeflate_alloc_compressor((int)level);
    if (compressors[level] == NULL) return 0;
    size_t bound = libdeflate_zlib_compress_bound(compressors[level], nbytes);
    void *out = H5allocate_memory(bound, 0);
    if (out == NULL) return 0;
    size_t n = libdeflate_zlib_compress(compressors[level], *buf, nbytes, out, bound);
    if (n == 0) {                  /* cannot happen with the bound: treated as a failure */
        H5free_memory(out);
        return 0;
    }
    H5free_memory(*buf);
    *buf = out;
    *buf_size = nbytes;            /* as H5Zdeflate.c: at most the buffer's size */
    count_deflated++;
    return n;
}

static size_t inflate_chunk(size_t nbytes, size_t *buf_size, void **buf)
{
    if (decompressor == NULL) decompressor = libdeflate_alloc_decompressor();
    if (decompressor == NULL) return 0;
    size_t nalloc = *buf_size > nbytes ? *buf_size : nbytes;
    if (last_inflated > nalloc) nalloc = last_inflated;
    if (nalloc == 0) nalloc = 1;
    for (;;) {
        void *out = H5allocate_memory(nalloc, 0);
        if (out == NULL) return 0;
        size_t n = 0;
        enum libdeflate_result r =
            libdeflate_zlib_decompress(decompressor, *buf, nbytes, out, nalloc, &n);
        if (r == LIBDEFLATE_SUCCESS) {
            H5free_memory(*buf);
            *buf = out;
            *buf_size = nalloc;
            last_inflated = n;
            count_inflated++;
            return n;
        }
        H5free_memory(out);
        if (r != LIBDEFLATE_INSUFFICIENT_SPACE || nalloc > ((size_t)-1) / 2) return 0;
        nalloc *= 2;
    }
}

/* H5Z_func_t: HDF5's filter interface. */
static size_t cfrd_deflate_filter(unsigned int flags, size_t cd_nelmts,
                                  const unsigned int cd_values[], size_t nbytes,
                                  size_t *buf_size, void **buf)
{
    size_t n = 0;
    if (cd_nelmts == 1 && cd_values[0] <= 9) {
        if (flags & H5Z_FLAG_REVERSE)
            n = inflate_chunk(nbytes, buf_size, buf);
        else
            n = deflate_chunk(cd_values[0], nbytes, buf_size, buf);
    }
    if (n == 0) count_failed++;
    return n;
}

static const H5Z_class2_t cfrd_deflate_class = {
    H5Z_CLASS_T_VERS,
    H5Z_FILTER_DEFLATE,   /* the standard id: files read by any HDF5 with zlib */
    1, 1,                 /* encoder and decoder present */
    "deflate",            /* HDF5's own name (written in version 1 filter pipeline messages) */
    NULL, NULL,           /* no can_apply, no set_local: as HDF5's own */
    cfrd_deflate_filter,
};

/* Put the libdeflate filter in the place of HDF5's deflate filter; call after each H5open.
 * 0 on success, -1 when HDF5 refused (its zlib filter then stays: the same files). */
int cfrd_deflate_register(void)
{
    if (!exit_hook) exit_hook = (atexit(free_coders) == 0);
    return H5Z_register(&cfrd_deflate_class) < 0 ? -1 : 0;
}

/* Chunks compressed and decompressed by this filter, and its failures, since the start. */
void cfrd_deflate_counts(long *deflated, long *inflated, long *failed)
{
    *deflated = count_deflated;
    *inflated = count_inflated;
    *failed = count_failed;
}
