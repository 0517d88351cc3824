#include "detail/pvd.h"

#include "detail/atomic_file.h"
#include "detail/vtk_errors.h"

#include "vessel/core/errors.h"

#include <vtkNew.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>

namespace vessel::detail {

std::vector<PvdEntry> read_pvd(const std::string& path)
{
    if (!std::filesystem::exists(path))
        throw IoError("read_pvd: file not found: " + path);
    vtkNew<vtkXMLDataParser> parser;
    parser->SetFileName(path.c_str());
    VtkErrors errors;  // keeps syntax errors off stderr; they go into our message
    errors.watch(parser);
    const int ok = parser->Parse() && !errors.failed();
    vtkXMLDataElement* root = ok ? parser->GetRootElement() : nullptr;
    if (!root || std::string(root->GetName()) != "VTKFile" || !root->GetAttribute("type") ||
        std::string(root->GetAttribute("type")) != "Collection")
        throw IoError("read_pvd: " + path +
                      " is not a ParaView collection (<VTKFile type=\"Collection\">)" +
                      (errors.failed() ? ": " + errors.message() : std::string()));
    vtkXMLDataElement* collection = root->FindNestedElementWithName("Collection");
    if (!collection)
        throw IoError("read_pvd: " + path + " has no <Collection> element");
    std::vector<PvdEntry> entries;
    for (int i = 0; i < collection->GetNumberOfNestedElements(); ++i)
    {
        vtkXMLDataElement* e = collection->GetNestedElement(i);
        if (std::string(e->GetName()) != "DataSet")
            continue;
        PvdEntry entry;
        const char* file = e->GetAttribute("file");
        if (!file)
            throw IoError("read_pvd: DataSet entry " + std::to_string(i) + " of " + path +
                          " has no 'file' attribute");
        entry.file = file;
        if (const char* t = e->GetAttribute("timestep"))
        {
            // VTK's GetScalarAttribute() reads "nan" (and any text) as 0; a time is a number.
            char* end = nullptr;
            entry.time = std::strtod(t, &end);
            if (end == t || *end != '\0' || !std::isfinite(entry.time))
                throw IoError("read_pvd: DataSet entry " + std::to_string(i) + " of " + path +
                              " has timestep=\"" + std::string(t).substr(0, 40) +
                              "\", not a finite number; give each step its time in seconds");
        }
        else
            entry.time = static_cast<double>(entries.size());
        e->GetScalarAttribute("part", entry.part);
        entries.push_back(entry);
    }
    if (entries.empty())
        throw IoError("read_pvd: " + path + " lists no DataSet files");
    return entries;
}

void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries)
{
    write_atomically(path, "write_pvd", [&](FILE* out) {
        std::fprintf(out,
                     "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
                     "byte_order=\"LittleEndian\">\n  <Collection>\n");
        for (const auto& e : entries)
            std::fprintf(out,
                         "    <DataSet timestep=\"%.15g\" group=\"\" part=\"%d\" file=\"%s\"/>\n",
                         e.time, e.part, e.file.c_str());
        std::fprintf(out, "  </Collection>\n</VTKFile>\n");
    });
}

}  // namespace vessel::detail
