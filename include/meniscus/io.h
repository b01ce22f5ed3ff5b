// File input and output: particle readers, sequence discovery, image writers.
// Nothing here exits or throws for bad input: every function returns a Result
// whose Error names the file and the problem.
#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/ext/vector_uint4_sized.hpp>

#include "meniscus/mesh.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

// ---------------------------------------------------------------- particles

// Hdf5: H5Part or PySPH's .hdf5, told apart by what the file holds; Npz:
// numpy's .npz (PySPH's or plain arrays). Both are read only, and optional in
// a build (particleFormatAvailable).
enum class ParticleFormat { Auto, Bgeo, VtkLegacy, Vtu, Ply, Csv, Xyz, Hdf5, Npz };

// Each parser reads a whole file already in memory. `name` is used in error
// messages only. Parsers return what the file holds (NaN positions included);
// readParticles()/parseParticles() then apply the common checks.
Result<ParticleSet> parseBgeo(ByteView data, const std::string& name);       // src/io/bgeo.cpp
Result<ParticleSet> parseVtkLegacy(ByteView data, const std::string& name);  // src/io/vtk_legacy.cpp
Result<ParticleSet> parseVtu(ByteView data, const std::string& name);        // src/io/vtu.cpp
Result<ParticleSet> parsePly(ByteView data, const std::string& name);        // src/io/ply.cpp
Result<ParticleSet> parseCsv(ByteView data, const std::string& name);        // src/io/text.cpp
Result<ParticleSet> parseXyz(ByteView data, const std::string& name);        // src/io/text.cpp

// Containers: files that hold several frames or several particle arrays. A
// frame inside one is named by a path into the file, HDF5 style, which
// readParticles, expandSequence and frameNumberOf understand:
//  - H5Part (.h5part, .h5; src/io/h5part.cpp): groups Step#0, Step#1, ...
//    of 1-D datasets x, y, z, ... (Bethel et al. 2005, the H5Part format).
//    One file is a whole sequence: expandSequence(run.h5part) gives
//    run.h5part/Step#0, run.h5part/Step#1, ... in step order, and the frame
//    number of run.h5part/Step#12 is 12. The file alone reads its first step
//    (with a warning when it has more).
//  - PySPH output (.hdf5: src/io/pysph_hdf5.cpp; .npz: src/io/npz.cpp), one
//    file per output step, one particle array per body (fluid, boundary,
//    ...): out_100.hdf5/fluid reads the array "fluid" (also written
//    out_100.hdf5/particles/fluid); the file alone reads "fluid", else the
//    first array with particles (with a warning when there are several). The
//    frame number of out_100.hdf5/fluid is 100, the file's.
//  - a plain .npz (numpy.savez of x, y, z, ... arrays; keys "fluid/x", ...
//    make bodies, named as out.npz/fluid).
// Names go through the shared alias table (x y z, u v w, rho, id, ...);
// PySPH's smoothing length h is kept as "h" (addRadiusFromSmoothingLength).
// `inner` is the part of the path after the file ("" for the default).
// Without HDF5 or libzip in the build these return an error saying so.
Result<ParticleSet> parseHdf5(ByteView data, const std::string& name, const std::string& inner = "");
Result<ParticleSet> parseNpz(ByteView data, const std::string& name, const std::string& inner = "");
// False for Hdf5 / Npz when the build lacks HDF5 / libzip.
bool particleFormatAvailable(ParticleFormat format);
// The steps of an H5Part file in step order ("Step#0", "Step#1", ...; empty
// for an HDF5 file that is not H5Part). Errors name the file.
Result<std::vector<std::string>> listH5PartSteps(const std::filesystem::path& path);
// The simulation time of each step of an H5Part file, in step order: the
// steps' "TimeValue" attribute (ParaView's H5Part reader reads it; "time" or
// "Time" when a writer named it so), seconds. Empty when a step has none.
Result<std::vector<double>> h5partStepTimes(const std::filesystem::path& path);
// The particle arrays of a PySPH .hdf5 / .npz (or the bodies of a plain
// .npz), in the file's order, with their particle counts (0: none stored).
struct ParticleArrayInfo {
    std::string name;
    std::size_t count = 0;
};
Result<std::vector<ParticleArrayInfo>> listParticleArrays(const std::filesystem::path& path);

// Format from the file name (.bgeo, .bgeo.gz, .vtk, .vtu, .ply, .csv, .xyz,
// .txt, .h5part, .h5, .hdf5, .npz); Auto when unknown.
ParticleFormat formatFromName(std::string_view name);

// The bundled demo frame: SPlisHSPlasH's dam break, r = 0.025 m, frame 21
// (t = 1.33 s), gzip BGEO (data/demo/), embedded in the library at build time.
inline constexpr const char* kDemoFrameName = "demo:dambreak_r0.025/ParticleData_Fluid_21.bgeo";
// The particle radius the simulation used (its scene file), so the demo shows the
// closed surface the simulation meant rather than the smaller spacing estimate.
inline constexpr float kDemoRadiusM = 0.025f;
std::span<const std::uint8_t> demoFrameBytes();

// Parse with the given (or detected) format, then: drop particles with
// non-finite positions (all attributes alike; the count goes into `warnings`),
// and reject sets with no particles left, unless `allowEmpty` (a file with no
// particles at all is then an empty set: e.g. a simulation's frame before its
// emitter started, which `simulate --resume` reads back).
Result<ParticleSet> parseParticles(ByteView data, const std::string& name,
                                   ParticleFormat format = ParticleFormat::Auto, bool allowEmpty = false);
// readParticles also takes a path into a container (see above:
// run.h5part/Step#3, out_100.hdf5/fluid); HDF5 files are read from the disk
// as needed, not whole into memory.
Result<ParticleSet> readParticles(const std::filesystem::path& path,
                                  ParticleFormat format = ParticleFormat::Auto, bool allowEmpty = false);

// Writes `set` to `path` in `format` (Auto: from the name, as formatFromName;
// .bgeo classic BGEO v5 as partio writes it (SPlisHSPlasH's export), .bgeo.gz
// the same gzip-compressed; .vtk binary legacy POLYDATA; .vtu / .vtp VTK XML with
// raw appended data; .ply binary little-endian). Every attribute is written
// (Float as float32, Int as int32) under names the readers above map back to
// the same attributes. A set with no particles gives a valid empty file
// (which readParticles() refuses, as it does every empty file). Refused,
// with an Error naming the file and nothing written: an unknown or
// unwritable format (CSV, XYZ, .geo), an attribute whose value count is not
// particles x components, two attributes of one name, a canonical attribute
// (id, velocity, density) of another type, an Int value beyond int32, a
// non-finite position. Written to a temporary name and renamed.
Status writeParticles(const std::filesystem::path& path, const ParticleSet& set,
                      ParticleFormat format = ParticleFormat::Auto);
// The format writeParticles writes `path` in (`format`, or from the name when
// Auto), or its refusal, naming the file, of one it cannot write: for
// checking an output before any work.
Result<ParticleFormat> writableFormatOf(const std::filesystem::path& path,
                                        ParticleFormat format = ParticleFormat::Auto);

// Whole file into memory. Error names the file.
Result<std::vector<std::uint8_t>> readFileBytes(const std::filesystem::path& path);

// gzip/zlib stream (auto-detected header) inflated into memory.
Result<std::vector<std::uint8_t>> inflateGzip(ByteView data, const std::string& name);

// ---------------------------------------------------------------- sequences

// Expands an input spec into an ordered frame list:
//  - an existing regular file: just that file (a .pvd collection: the files it
//    lists, in timestep order; see readPvd below; an H5Part file: its steps,
//    as paths into it, run.h5part/Step#0, ..., in step order);
//  - a path into a container (run.h5part/Step#3, out.hdf5/fluid): itself; a
//    pattern of containers with a path into each (out_*.hdf5/fluid): the
//    pattern's files, each with that path;
//  - a directory: every particle file in it (known extensions);
//  - a printf pattern with one integer conversion (frame_%04d.ply, f_%d.bgeo);
//  - a glob pattern with * and ? in the file name (ParticleData_Fluid_*.bgeo).
// Frames are sorted in natural numeric order ("_2" before "_10"); H5Part
// files found in a directory or by a pattern give their steps in their place.
// An empty result is an error that names the spec.
Result<std::vector<std::filesystem::path>> expandSequence(const std::string& spec);

// True when `spec` names more than a single file (a directory, a pattern, a
// .pvd collection or an H5Part file of more than one step).
bool isSequenceSpec(const std::string& spec);

// A ParaView data collection (.pvd, `<VTKFile type="Collection">`), the time
// series index ParaView writes beside .vtu/.vtp frames (src/io/pvd.cpp).
// expandSequence() gives a .pvd's files in this order: an existing file
// named *.pvd is the sequence it lists.
struct PvdCollection {
    std::vector<std::filesystem::path> files;  // ascending timestep; relative ones joined to the .pvd's folder
    std::vector<double> times;                 // files[i]'s timestep (file order 0, 1, ... when none has one)
    bool timed = false;                        // the file gave the timesteps (not the file order)
    std::vector<long long> parts;              // files[i]'s part (the lowest of its timestep; usually 0)
    std::vector<std::string> warnings;         // e.g. the datasets of further parts left out
};
// One file per timestep: the DataSet with the lowest `part` (0 as ParaView
// writes it); the others are counted in `warnings`. Errors (naming `name`):
// not XML, not a VTKFile of type Collection, no DataSet, a DataSet without a
// file, a timestep that is not a finite number, only some DataSets with a
// timestep, a part that is not a whole number from 0, two files for one
// timestep and part. `baseDir` is joined to relative file names; nothing is
// read from the disk.
Result<PvdCollection> parsePvd(ByteView data, const std::string& name, const std::filesystem::path& baseDir);
// parsePvd of a file, relative names from its folder; also an error (naming
// the .pvd) when a listed file does not exist.
Result<PvdCollection> readPvd(const std::filesystem::path& path);
// True for a name ending in .pvd (any case).
bool isPvdName(std::string_view name);
// Writes a ParaView collection listing `files` (each relative to the .pvd's
// folder when it can be) with `times`, one DataSet of part 0 each, as
// parsePvd reads it back. An error naming the .pvd when the counts differ or a
// time is not finite; written to a temporary name and renamed.
Status writePvd(const std::filesystem::path& path, const std::vector<std::filesystem::path>& files,
                const std::vector<double>& times);

// Natural order comparison: digit runs compare by value.
bool naturalLess(std::string_view a, std::string_view b);

// Output name for frame `index` (0-based position) / `number` (the frame's
// own number if known) from a printf pattern such as out_%04d.png.
Result<std::string> formatFramePattern(const std::string& pattern, long number);

// The frame rate of a sequence's times t_0 < t_1 < ... (seconds): 1 / dt when
// they are evenly spaced (every step within 0.1 % of the mean step), else none
// (fewer than two times, uneven or non-increasing steps).
std::optional<double> evenFrameRate(std::span<const double> times);
// The frame rate the data of a sequence input carries, if any: a ParaView
// collection's evenly spaced timesteps, or an H5Part file's evenly spaced
// step times (h5partStepTimes; a .pvd without timesteps, an H5Part file
// without times and numbered files carry none). Errors name the file.
Result<std::optional<double>> frameRateOfInput(const std::filesystem::path& input);

// ---------------------------------------------------------------- images

// The 8-bit sRGB image writePng writes for linear RGBA in [0,1]: R, G, B by
// the exact sRGB transfer function, alpha linear; clamped, rounded, NaN -> 0.
Image<glm::u8vec4> encodeSrgb8(const Image<glm::vec4>& linearRgba);

// The folders above an output file, made where missing: every command makes
// its outputs' folders this one way (images, movies, meshes, particles), while
// the writers themselves refuse a missing folder. An error names the file and
// says which folder could not be made and why.
Status makeOutputFolders(const std::filesystem::path& file);

// Write-then-rename for a file written over time (a movie, frame by frame):
// write to tmp(), then commit() renames it onto the path given to begin()
// (through a symbolic link, which stays); a PendingFile destroyed or
// discard()ed before that removes tmp(), so a failed or interrupted write
// leaves no partial file. tmp() is hidden and in the same directory.
class PendingFile {
public:
    static Result<PendingFile> begin(const std::filesystem::path& path);
    PendingFile(PendingFile&& other) noexcept;
    PendingFile& operator=(PendingFile&& other) noexcept;
    PendingFile(const PendingFile&) = delete;
    PendingFile& operator=(const PendingFile&) = delete;
    ~PendingFile();
    const std::filesystem::path& tmp() const { return tmp_; }
    Status commit();
    void discard();

private:
    PendingFile(std::filesystem::path path, std::filesystem::path dest, std::filesystem::path tmp)
        : path_(std::move(path)), dest_(std::move(dest)), tmp_(std::move(tmp)) {}
    std::filesystem::path path_, dest_, tmp_;  // as given, its final target, the temporary
};

// 8-bit PNG, sRGB-encoded from linear RGBA in [0,1] (alpha stays linear).
// withAlpha=false writes RGB. Written to a temporary name and renamed.
Status writePng(const std::filesystem::path& path, const Image<glm::vec4>& linearRgba,
                bool withAlpha = true);
// The same for 8-bit RGBA already sRGB-encoded (e.g. a window's framebuffer
// read back), written as it is.
Status writePng(const std::filesystem::path& path, const Image<glm::u8vec4>& srgba8, bool withAlpha = true);

// One named float32 channel of an EXR file.
struct ExrChannel {
    std::string name;
    const Image<float>* image = nullptr;
};

// OpenEXR, float32 channels, scanline 0 = top row, ZIP compression.
// All channels must have the same size. Written to a temporary name and renamed.
Status writeExr(const std::filesystem::path& path, const std::vector<ExrChannel>& channels);

// The per-pixel outputs of a render (arbitrary output variables). Images that
// are empty are omitted from the EXR.
struct Aovs {
    Image<glm::vec4> color;    // linear RGB, A = alpha (1 over the studio) -> R G B A
                               // (1 where rawDepth, else depth, is finite)  -> coverage
    Image<float> depth;        // smoothed linear eye depth, +inf = none -> Z
    Image<float> rawDepth;     // splatted linear eye depth, +inf = none -> Zraw
    Image<glm::vec3> normal;   // view-space unit normal, 0 = none       -> N.X N.Y N.Z
    Image<float> thickness;    // metres                                 -> T
    Image<float> noise;        // surface noise N, 0 = none (with noise on) -> Noise
    Image<float> foam;         // foam cover in [0, 1] (with noise on)    -> foam
    Image<float> whitening;    // velocity whitening map in [0, 1] (with it on) -> whitening
    Image<float> spray;        // spray drops' cover in [0, 1] (with spray on) -> spray
    Image<float> silhouette;   // silhouette map S in [0, 1], 0 = no fluid (with it on) -> silhouette
    Image<float> fluid;        // the nearest fluid's index, -1 = none (particles with a fluid index) -> fluid
};
Status writeExrAovs(const std::filesystem::path& path, const Aovs& aovs);

// ---------------------------------------------------------------- meshes

// Binary little-endian PLY (vertex x y z nx ny nz float, face vertex_indices
// uchar/uint), or Wavefront OBJ (v, vn, f v//vn, 1-based). Both open in
// Blender, Houdini, ParaView, MeshLab. Written to a temporary name and renamed;
// a mesh TriangleMesh::validate() refuses (normals are optional) is an error
// naming the file, and nothing is written.
// Vertex attributes (TriangleMesh::attributes) go into PLY (float properties
// NAME, or NAME_x/_y/_z) and both VTK formats (point data); OBJ has no place
// for them.
enum class MeshFormat { Ply, Obj, Vtp, VtkLegacy };
// The format a mesh file's extension names, in any case: .ply, .obj, .vtp (VTK
// XML PolyData) or .vtk (legacy binary POLYDATA); any other extension, or
// none, is an error naming the file.
Result<MeshFormat> meshFormatOf(const std::filesystem::path& path);
Status writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh, MeshFormat format);

// Reads a triangle mesh (src/io/mesh_reader.cpp): Wavefront OBJ (v, vn, f with
// v, v/t, v//n or v/t/n corners, negative indices, polygons fanned into
// triangles) or PLY, ascii or binary (vertex x y z [nx ny nz], face
// vertex_indices or vertex_index lists). Normals are kept when the file gives
// one per vertex (OBJ: every corner names its vertex's own normal, as
// writeMesh writes them), else the mesh has none. The format comes from the
// extension (.obj, .ply, any case). A file with no faces, an index out of
// range, a truncated file or a non-finite position is an Error naming the file.
Result<TriangleMesh> readMesh(const std::filesystem::path& path);
// The same for a file already in memory; `name` is used in error messages only.
Result<TriangleMesh> parseObjMesh(ByteView data, const std::string& name);
Result<TriangleMesh> parsePlyMesh(ByteView data, const std::string& name);

}  // namespace meniscus

namespace meniscus {
// The frame number a file name carries: the last run of digits in its name
// without extensions (ParticleData_Fluid_21.bgeo -> 21), or -1 when none.
long frameNumberFromName(std::string_view fileName);
// The frame number of a frame path (as expandSequence gives them): its file
// name's, and for a path into a container the step's (run.h5part/Step#12 ->
// 12) or else the container's (out_100.hdf5/fluid -> 100); -1 when none.
long frameNumberOf(const std::filesystem::path& framePath);
}  // namespace meniscus
