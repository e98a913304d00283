/*
 * vtk_collection: .pvd and .vtu.series time indexes (see vtk_collection.h).
 *
 * Both files are small and rewritten whole through atomic_file; stdio errors
 * are sticky, so afile_commit's ferror check catches any failed write.
 */
#include "io/vtk_collection.h"

#include "io/atomic_file.h"
#include "io/vtk_writer.h"

#include <math.h>
#include <stdio.h>

/* s as a JSON string body: quote, backslash and control characters escaped;
 * other bytes pass through (names are UTF-8). */
static void vtk_json_escape(FILE *f, const char *s)
{
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') fprintf(f, "\\%c", c);
        else if (c < 0x20) fprintf(f, "\\u%04x", (unsigned)c);
        else fputc(c, f);
    }
}

static void vtk_collection_pvd(FILE *f, const double *times, const char *const *files, size_t n)
{
    char t[40];
    fputs("<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          "  <Collection>\n",
          f);
    for (size_t i = 0; i < n; i++) {
        vtk_format_double(times[i], t, sizeof t);
        fprintf(f, "    <DataSet timestep=\"%s\" group=\"\" part=\"0\" file=\"", t);
        vtk_xml_escape(f, files[i]);
        fputs("\"/>\n", f);
    }
    fputs("  </Collection>\n</VTKFile>\n", f);
}

static void vtk_collection_series(FILE *f, const double *times, const char *const *files, size_t n)
{
    char t[40];
    fputs("{\n  \"file-series-version\" : \"1.0\",\n  \"files\" : [", f);
    for (size_t i = 0; i < n; i++) {
        vtk_format_double(times[i], t, sizeof t);
        fputs(i ? ",\n    { \"name\" : \"" : "\n    { \"name\" : \"", f);
        vtk_json_escape(f, files[i]);
        fprintf(f, "\", \"time\" : %s }", t);
    }
    fputs(n ? "\n  ]\n}\n" : "]\n}\n", f);
}

/* Write one index file atomically with the given body writer. */
static int vtk_collection_file(const char *path, const double *times, const char *const *files,
                               size_t n,
                               void (*body)(FILE *, const double *, const char *const *, size_t),
                               sl_err *err)
{
    afile af;
    FILE *f = afile_open(&af, path, err);
    if (!f) return 1;
    body(f, times, files, n);
    return afile_commit(&af, err);
}

int vtk_collection_write(const char *pvd_path, const char *series_path, const double *times,
                         const char *const *files, size_t n, sl_err *err)
{
    const char *path = pvd_path ? pvd_path : series_path ? series_path : "(no path)";
    for (size_t i = 0; i < n; i++) {
        /* JSON has no NaN or Inf, and ParaView could not sort them anyway. */
        if (!isfinite(times[i]) || !files[i]) {
            sl_err_set(err, "cannot write '%s': entry %zu has %s", path, i,
                       files[i] ? "a time that is not finite" : "no file name");
            return 1;
        }
    }
    if (pvd_path && vtk_collection_file(pvd_path, times, files, n, vtk_collection_pvd, err))
        return 1;
    if (series_path &&
        vtk_collection_file(series_path, times, files, n, vtk_collection_series, err))
        return 1;
    return 0;
}
