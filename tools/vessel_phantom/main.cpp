// vessel-phantom: writes a synthetic vessel surface (carotid bifurcation, helical tube or random
// vessel tree) to a mesh file.
#include <OpenMesh/Core/IO/MeshIO.hh>

#include "pulse_files.h"

#include "vessel/cut/boundary.h"
#include "vessel/core/errors.h"
#include "vessel/fields/field_series.h"
#include "vessel/phantom/phantom.h"
#include "vessel/fields/pulse_series.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace {

std::string lower_extension(const std::string& path)
{
    const auto dot = path.rfind('.');
    if (dot == std::string::npos)
        return {};
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{
        "vessel-phantom: write a synthetic vessel surface mesh.\n"
        "  aneurysm straight parent artery with a spherical sac on its side (lateral\n"
        "           aneurysm); 2 boundary loops (3 with --branch-radius), lengths in mm\n"
        "  carotid  common carotid splitting into internal (with sinus bulb and stenosis) and\n"
        "           external carotid; 3 boundary loops, lengths in mm\n"
        "  helix    open tube swept along a helix with a rotation-minimizing frame and\n"
        "           staggered rings; 2 boundary loops\n"
        "  tree     seeded random vessel tree with one inlet and N outlets\n"
        "All surfaces are open, genus 0, 2-manifold, with outward normals.",
        "vessel-phantom"};
    app.get_formatter()->column_width(36);

    std::string kind, output;
    app.add_option("kind", kind, "Phantom to generate: aneurysm, carotid, helix or tree")
        ->required()
        ->check(CLI::IsMember({"aneurysm", "carotid", "helix", "tree"}));
    app.add_option("-o,--output", output,
                   "Output mesh file; the format follows the extension: .ply (binary), .obj, "
                   ".off or .stl (binary)")
        ->required();

    double edge_length = 0.0;
    app.add_option("--edge-length", edge_length,
                   "Target edge length (carotid, tree: default 0.5 mm; aneurysm: 0.4 mm; helix: "
                   "slanted edge length, default = spacing around the tube)");

    vessel::AneurysmPhantomOptions aneurysm;
    app.add_option("--sac-radius", aneurysm.sac_radius,
                   "aneurysm: radius of the sac (mm), 0.75 to 3 x the parent's 2 mm")
        ->capture_default_str();
    app.add_option("--branch-radius", aneurysm.branch_radius,
                   "aneurysm: radius of a small branch off the sac (mm; 0 = none), a third "
                   "loop whose cut crosses the sac")
        ->capture_default_str();
    app.add_option("--taper", aneurysm.taper,
                   "aneurysm: how much the parent narrows from inlet to outlet, as a fraction of "
                   "its radius (0 to 0.5; 0 = straight, its two end loops tie)")
        ->capture_default_str();

    vessel::CarotidPhantomOptions carotid;
    app.add_option("--stenosis", carotid.stenosis,
                   "carotid: fractional diameter reduction of the ICA narrowing, 0 to 0.8")
        ->capture_default_str();
    app.add_option("--branch-angle", carotid.branch_angle_deg,
                   "carotid: angle of ICA and ECA to the CCA axis (degrees)")
        ->capture_default_str();
    app.add_option("--cca-radius", carotid.cca_radius, "carotid: CCA radius (mm)")
        ->capture_default_str();
    app.add_option("--ica-radius", carotid.ica_radius, "carotid: ICA radius (mm)")
        ->capture_default_str();
    app.add_option("--eca-radius", carotid.eca_radius, "carotid: ECA radius (mm)")
        ->capture_default_str();
    app.add_option("--cca-length", carotid.cca_length, "carotid: CCA length (mm)")
        ->capture_default_str();
    app.add_option("--ica-length", carotid.ica_length, "carotid: ICA length (mm)")
        ->capture_default_str();
    app.add_option("--eca-length", carotid.eca_length, "carotid: ECA length (mm)")
        ->capture_default_str();

    vessel::HelicalTubeOptions helix;
    app.add_option("--turns", helix.turns, "helix: number of turns of the centerline")
        ->capture_default_str();
    app.add_option("--tube-radius", helix.tube_radius, "helix: tube radius")
        ->capture_default_str();
    app.add_option("--helix-radius", helix.helix_radius,
                   "helix: radius of the helical centerline (0 = straight)")
        ->capture_default_str();
    app.add_option("--pitch", helix.pitch, "helix: rise of the centerline per turn")
        ->capture_default_str();
    app.add_option("--n-around", helix.n_around, "helix: vertices around the tube")
        ->capture_default_str();

    vessel::TreePhantomOptions tree;
    app.add_option("--outlets", tree.outlets, "tree: number of outlets, 1 to 30")
        ->capture_default_str();
    app.add_option("--seed", tree.seed, "tree: random seed (same seed, same mesh)")
        ->capture_default_str();
    app.add_option("--root-radius", tree.root_radius, "tree: inlet radius")
        ->capture_default_str();

    std::string pulse_prefix;
    app.add_option("--pulse", pulse_prefix,
                   "Also write a travelling WSS-like pulse over the mesh (1.8 s, 90 steps, Pa) as "
                   "PREFIX.pvd (+ PREFIX/PREFIX_NNN.vtp), PREFIX.csv (wide) and PREFIX-long.csv "
                   "(long); vertex ids are those of OUTPUT");
    vessel::PulseSeriesOptions pulse;
    app.add_option("--pulse-steps", pulse.steps, "With --pulse: number of time steps")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();

    bool quiet = false;
    app.add_flag("-q,--quiet", quiet, "Do not print the mesh summary");

    CLI11_PARSE(app, argc, argv);

    try
    {
        // Reject options that belong to another phantom rather than silently ignoring them.
        const std::vector<std::pair<std::string, std::vector<std::string>>> owners = {
            {"aneurysm", {"--sac-radius", "--branch-radius"}},
            {"carotid",
             {"--stenosis", "--branch-angle", "--cca-radius", "--ica-radius", "--eca-radius",
              "--cca-length", "--ica-length", "--eca-length"}},
            {"helix", {"--turns", "--tube-radius", "--helix-radius", "--pitch", "--n-around"}},
            {"tree", {"--outlets", "--seed", "--root-radius"}}};
        for (const auto& [owner, names] : owners)
            for (const auto& name : names)
                if (owner != kind && app.count(name) > 0)
                    throw vessel::InvalidInputError(name + " only applies to '" + owner +
                                                    "', not to '" + kind + "'");

        const std::string ext = lower_extension(output);
        if (ext != "ply" && ext != "obj" && ext != "off" && ext != "stl")
            throw vessel::InvalidInputError("unsupported output extension '." + ext +
                                            "' in " + output + "; use .ply, .obj, .off or .stl");

        const bool has_edge_length = app.count("--edge-length") > 0;
        vessel::Mesh mesh;
        if (kind == "aneurysm")
        {
            if (has_edge_length)
                aneurysm.edge_length = edge_length;
            mesh = vessel::aneurysm_phantom(aneurysm);
        }
        else if (kind == "carotid")
        {
            if (has_edge_length)
                carotid.edge_length = edge_length;
            mesh = vessel::carotid_phantom(carotid);
        }
        else if (kind == "helix")
        {
            if (has_edge_length)
                helix.edge_length = edge_length;
            mesh = vessel::helical_tube(helix);
        }
        else
        {
            if (has_edge_length)
                tree.edge_length = edge_length;
            mesh = vessel::tree_phantom(tree);
        }

        OpenMesh::IO::Options write_options;
        if (ext == "ply" || ext == "stl")
            write_options += OpenMesh::IO::Options::Binary;
        if (!OpenMesh::IO::write_mesh(mesh, output, write_options))
            throw vessel::IoError("could not write " + output);
        if (!pulse_prefix.empty())
        {
            const vessel::TimeSeries series = vessel::travelling_pulse(mesh, pulse);
            vessel::cli::write_pulse_files(pulse_prefix, vessel::to_raw_mesh(mesh), series,
                                           pulse.name);
            if (!quiet)
                std::cout << "pulse: " << series.size() << " steps over " << pulse.duration_s
                          << " s -> " << pulse_prefix << ".pvd, .csv, -long.csv\n";
        }
        if (!quiet)
            std::cout << kind << ": " << mesh.n_vertices() << " vertices, " << mesh.n_faces()
                      << " faces, " << vessel::boundary_loops(mesh).size()
                      << " boundary loops, mean edge length " << vessel::mean_edge_length(mesh)
                      << " -> " << output << "\n";
    }
    catch (const std::exception& e)
    {
        std::cerr << "vessel-phantom: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
