#include "vessel/io/vtk_io.h"

#include "detail/atomic_file.h"
#include "detail/vtk_check.h"
#include "detail/vtk_errors.h"
#include "vessel/core/errors.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkErrorCode.h>
#include <vtkExecutive.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkPolyDataWriter.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <functional>
#include <tuple>

namespace vessel {

namespace {

std::string lower_extension(const std::string& path)
{
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

FieldType field_type(int vtk_type)
{
    switch (vtk_type)
    {
        case VTK_FLOAT:
            return FieldType::Float32;
        case VTK_DOUBLE:
            return FieldType::Float64;
        case VTK_LONG:
        case VTK_UNSIGNED_LONG:
        case VTK_LONG_LONG:
        case VTK_UNSIGNED_LONG_LONG:
        case VTK_ID_TYPE:
            return FieldType::Int64;
        default:
            return FieldType::Int32;
    }
}

std::vector<Field> read_arrays(vtkFieldData* data, FieldLocation location)
{
    std::vector<Field> out;
    for (int i = 0; i < data->GetNumberOfArrays(); ++i)
    {
        vtkDataArray* array = data->GetArray(i);  // null for string and other non-numeric arrays
        if (!array)
            continue;
        Field f;
        f.name = array->GetName() ? array->GetName() : "array" + std::to_string(i);
        f.location = location;
        f.type = field_type(array->GetDataType());
        const int nc = array->GetNumberOfComponents();
        f.values.resize(array->GetNumberOfTuples(), nc);
        for (vtkIdType t = 0; t < array->GetNumberOfTuples(); ++t)
            for (int c = 0; c < nc; ++c)
                f.values(t, c) = array->GetComponent(t, c);
        out.push_back(std::move(f));
    }
    return out;
}

std::vector<Eigen::Vector3d> points_of(vtkDataSet* data)
{
    std::vector<Eigen::Vector3d> points(static_cast<std::size_t>(data->GetNumberOfPoints()));
    for (std::size_t i = 0; i < points.size(); ++i)
        data->GetPoint(static_cast<vtkIdType>(i), points[i].data());
    return points;
}

// Runs a VTK XML reader on \p path with VTK's errors turned into IoError; \p check (e.g. the
// structure checks of vtk_check.h) runs once the file is known to be a \p type file.
template <class Reader>
void run_xml_reader(Reader* reader, const std::string& path, const std::string& caller,
                    const std::string& type, const std::function<void()>& check = {})
{
    detail::VtkErrors errors;
    errors.watch(reader);
    errors.watch(reader->GetExecutive());
    reader->SetReaderErrorObserver(errors.command());
    reader->SetParserErrorObserver(errors.command());
    if (!reader->CanReadFile(path.c_str()))
        throw IoError(caller + ": " + path + " is not a VTK XML " + type +
                      " file (<VTKFile type=\"" + type + "\">)");
    if (check)
        check();
    reader->SetFileName(path.c_str());
    reader->Update();
    if (errors.failed())
        throw IoError(caller + ": VTK could not read " + path + ": " + errors.message());
}

PolyData convert(vtkPolyData* poly, const std::string& path)
{
    const auto refuse_cells = [&](vtkIdType n, const char* what) {
        if (n > 0)
            throw IoError("read_polydata: " + path + " holds " + std::to_string(n) + " " + what +
                          "; a vessel wall is a surface of polygons: remove them (ParaView: "
                          "Extract Surface, then Triangulate) and save again");
    };
    refuse_cells(poly->GetNumberOfVerts(), "vertex cells");
    refuse_cells(poly->GetNumberOfLines(), "line cells");
    refuse_cells(poly->GetNumberOfStrips(), "triangle strips");
    PolyData out;
    const vtkIdType np = poly->GetNumberOfPoints();
    out.mesh.points = points_of(poly);
    vtkCellArray* polys = poly->GetPolys();
    out.mesh.faces.reserve(static_cast<std::size_t>(polys->GetNumberOfCells()));
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
        out.mesh.faces.emplace_back(ids, ids + n);
    out.point_data = read_arrays(poly->GetPointData(), FieldLocation::Point);
    out.cell_data = read_arrays(poly->GetCellData(), FieldLocation::Cell);
    if (vtkDataArray* tc = poly->GetPointData()->GetTCoords(); tc && tc->GetName())
        out.tcoords = tc->GetName();
    check_fields(out.point_data, static_cast<int>(np), static_cast<int>(out.mesh.faces.size()),
                 path);
    check_fields(out.cell_data, static_cast<int>(np), static_cast<int>(out.mesh.faces.size()),
                 path);
    return out;
}

vtkSmartPointer<vtkDataArray> make_array(const Field& f)
{
    const int vtk_type = f.type == FieldType::Float32   ? VTK_FLOAT
                         : f.type == FieldType::Float64 ? VTK_DOUBLE
                         : f.type == FieldType::Int32   ? VTK_INT
                                                        : VTK_TYPE_INT64;
    auto a = vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(vtk_type));
    a->SetName(f.name.c_str());
    a->SetNumberOfComponents(f.components());
    a->SetNumberOfTuples(f.rows());
    for (Eigen::Index t = 0; t < f.rows(); ++t)
        for (int c = 0; c < f.components(); ++c)
            a->SetComponent(t, c, f.values(t, c));
    return a;
}

// vtkXMLPolyDataWriter and vtkPolyDataWriter share Write() but no base class with it.
template <class Writer>
std::pair<int, std::string> run_writer(Writer* writer, const detail::VtkErrors& errors)
{
    // The error code catches a stream failure (e.g. disk full) that VTK reports nowhere else.
    const int ok = writer->Write() && !errors.failed() && writer->GetErrorCode() == 0;
    std::string message = errors.message();
    const unsigned long code = writer->GetErrorCode();
    if (code == vtkErrorCode::OutOfDiskSpaceError)
        message = "out of disk space or over the file size limit (ulimit -f)";
    else if (message.empty() && code != 0)
        message = "VTK error code " + std::to_string(code);
    message = message.substr(0, message.find('\n'));  // one line on stderr
    return {ok, message};
}

vtkSmartPointer<vtkPolyData> to_vtk(const PolyData& data, const std::string& path)
{
    const int np = static_cast<int>(data.mesh.points.size());
    const int nf = static_cast<int>(data.mesh.faces.size());
    check_fields(data.point_data, np, nf, "write_polydata(" + path + ")");
    check_fields(data.cell_data, np, nf, "write_polydata(" + path + ")");
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(np);
    for (int i = 0; i < np; ++i)
        points->SetPoint(i, data.mesh.points[i].data());
    poly->SetPoints(points);
    vtkNew<vtkCellArray> polys;
    for (const auto& face : data.mesh.faces)
    {
        std::vector<vtkIdType> ids(face.begin(), face.end());
        for (auto id : ids)
            if (id < 0 || id >= np)
                throw InvalidInputError("write_polydata: a face refers to point " +
                                        std::to_string(id) + " of " + std::to_string(np));
        polys->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
    }
    poly->SetPolys(polys);
    for (const auto& f : data.point_data)
    {
        auto a = make_array(f);
        if (f.name == data.tcoords)
            poly->GetPointData()->SetTCoords(a);
        else
            poly->GetPointData()->AddArray(a);
    }
    for (const auto& f : data.cell_data)
        poly->GetCellData()->AddArray(make_array(f));
    return poly;
}

}  // namespace

bool is_vtk_path(const std::string& path)
{
    const std::string ext = lower_extension(path);
    return ext == ".vtp" || ext == ".vtk" || ext == ".vtu";
}

bool register_vtk_formats()
{
    const MeshReader reader = [](const std::string& path) { return read_polydata(path).mesh; };
    register_mesh_reader(".vtp", reader);
    register_mesh_reader(".vtk", reader);
    register_mesh_reader(".vtu", reader);
    return true;
}

PolyData read_polydata(const std::string& path)
{
    if (!std::filesystem::exists(path))
        throw IoError("read_polydata: file not found: " + path);
    const std::string ext = lower_extension(path);
    if (ext == ".vtu")
    {
        UnstructuredGrid grid = read_unstructured_grid(path);
        if (grid.is_volume())
            throw IoError("read_polydata: " + path +
                          " holds volume cells (a 3D mesh), not a wall surface; give the wall "
                          "(e.g. SimVascular's walls_combined.vtp) as the mesh and the .vtu as "
                          "--fields, matched by GlobalNodeID (docs/fields.md)");
        return std::move(grid.data);
    }
    vtkSmartPointer<vtkPolyData> poly;
    if (ext == ".vtp")
    {
        vtkNew<vtkXMLPolyDataReader> reader;
        run_xml_reader(reader.Get(), path, "read_polydata", "PolyData",
                       [&] { detail::check_vtp(path); });
        poly = reader->GetOutput();
    }
    else if (ext == ".vtk")
    {
        vtkNew<vtkPolyDataReader> reader;
        detail::VtkErrors errors;
        errors.watch(reader);
        errors.watch(reader->GetExecutive());
        reader->SetFileName(path.c_str());
        if (!detail::check_legacy_vtk(path))
            throw IoError("read_polydata: " + path +
                          " is not a legacy VTK POLYDATA file (DATASET POLYDATA); extract the "
                          "surface first (ParaView: Extract Surface) and save it as .vtp");
        reader->ReadAllScalarsOn();
        reader->ReadAllVectorsOn();
        reader->ReadAllNormalsOn();
        reader->ReadAllTensorsOn();
        reader->ReadAllTCoordsOn();
        reader->ReadAllFieldsOn();
        reader->Update();
        if (errors.failed())
            throw IoError("read_polydata: VTK could not read " + path + ": " + errors.message());
        poly = reader->GetOutput();
    }
    else
        throw IoError("read_polydata: unknown extension '" + ext + "' (" + path +
                      "); use .vtp, .vtk or .vtu");
    if (!poly || poly->GetNumberOfPoints() == 0)
        throw IoError("read_polydata: no points in " + path + " (empty or truncated file?)");
    return convert(poly, path);
}

UnstructuredGrid read_unstructured_grid(const std::string& path)
{
    if (!std::filesystem::exists(path))
        throw IoError("read_unstructured_grid: file not found: " + path);
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    run_xml_reader(reader.Get(), path, "read_unstructured_grid", "UnstructuredGrid");
    vtkUnstructuredGrid* grid = reader->GetOutput();
    if (!grid || grid->GetNumberOfPoints() == 0)
        throw IoError("read_unstructured_grid: no points in " + path +
                      " (empty or truncated file?)");
    UnstructuredGrid result;
    PolyData& out = result.data;
    const vtkIdType np = grid->GetNumberOfPoints();
    out.mesh.points = points_of(grid);
    out.point_data = read_arrays(grid->GetPointData(), FieldLocation::Point);
    const vtkIdType nc = grid->GetNumberOfCells();
    bool surface = nc > 0;
    for (vtkIdType c = 0; surface && c < nc; ++c)
    {
        const int type = grid->GetCellType(c);
        surface = type == VTK_TRIANGLE || type == VTK_QUAD || type == VTK_POLYGON;
    }
    if (surface)
    {
        out.mesh.faces.reserve(static_cast<std::size_t>(nc));
        vtkNew<vtkIdList> ids;
        for (vtkIdType c = 0; c < nc; ++c)
        {
            grid->GetCellPoints(c, ids);
            auto& face = out.mesh.faces.emplace_back();
            for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
                face.push_back(static_cast<int>(ids->GetId(k)));
        }
        out.cell_data = read_arrays(grid->GetCellData(), FieldLocation::Cell);
    }
    else
        for (const auto& f : read_arrays(grid->GetCellData(), FieldLocation::Cell))
            result.volume_cell_arrays.push_back(f.name);
    const int nf = static_cast<int>(out.mesh.faces.size());
    check_fields(out.point_data, static_cast<int>(np), nf, path);
    check_fields(out.cell_data, static_cast<int>(np), nf, path);
    return result;
}

void write_polydata(const std::string& path, const PolyData& data, const VtkWriteOptions& options)
{
    const std::string ext = lower_extension(path);
    if (ext != ".vtp" && ext != ".vtk")
        throw InvalidInputError("write_polydata: '" + path + "' must end in .vtp or .vtk");
    auto poly = to_vtk(data, path);
    detail::TempFile temp(path, "write_polydata");
    const std::string& tmp = temp.path();
    int ok = 0;
    std::string message;
    if (ext == ".vtp")
    {
        vtkNew<vtkXMLPolyDataWriter> writer;
        detail::VtkErrors errors;
        errors.watch(writer);
        errors.watch(writer->GetExecutive());
        writer->SetInputData(poly);
        writer->SetFileName(tmp.c_str());
        if (options.encoding == VtkEncoding::Ascii)
            writer->SetDataModeToAscii();
        else if (options.encoding == VtkEncoding::Binary)
            writer->SetDataModeToBinary();
        else
        {
            writer->SetDataModeToAppended();
            writer->EncodeAppendedDataOff();
        }
        switch (options.compressor)
        {
        case VtkCompressor::None: writer->SetCompressorTypeToNone(); break;
        case VtkCompressor::ZLib: writer->SetCompressorTypeToZLib(); break;
        case VtkCompressor::LZ4: writer->SetCompressorTypeToLZ4(); break;
        case VtkCompressor::LZMA: writer->SetCompressorTypeToLZMA(); break;
        }
        std::tie(ok, message) = run_writer(writer.Get(), errors);
    }
    else
    {
        if (options.encoding == VtkEncoding::Appended)
            throw InvalidInputError(
                "write_polydata: legacy .vtk has no appended encoding; use "
                "Ascii or Binary, or write .vtp (" +
                path + ")");
        vtkNew<vtkPolyDataWriter> writer;
        detail::VtkErrors errors;
        errors.watch(writer);
        errors.watch(writer->GetExecutive());
        writer->SetInputData(poly);
        writer->SetFileName(tmp.c_str());
        writer->SetFileVersion(vtkPolyDataWriter::VTK_LEGACY_READER_VERSION_4_2);
        if (options.encoding == VtkEncoding::Ascii)
            writer->SetFileTypeToASCII();
        else
            writer->SetFileTypeToBinary();
        std::tie(ok, message) = run_writer(writer.Get(), errors);
    }
    if (!ok)
        throw IoError("write_polydata: VTK could not write " + path + ": " + message);
    temp.commit();
}

}  // namespace vessel
