#include "output_hdf5.hpp"

#include "hdf5_io.hpp"

#include <hdf5.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include <mpmice/kernels/errors.hpp>
#include <mpmice/kernels/particle_grid.hpp>

namespace mpmice {
namespace {

// Write this rank's block (C order) of a dataset of `global` dims at `offset`.
void write_block(hid_t file, const std::string& name, const std::vector<hsize_t>& global,
                 const std::vector<hsize_t>& offset, const std::vector<hsize_t>& count,
                 std::vector<double> local) {
  collective_block_io(file, name, true, global, offset, count, local.empty() ? nullptr : local.data());
}

void write_attribute(hid_t file, const char* name, double value) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = H5Acreate2(file, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attr, H5T_NATIVE_DOUBLE, &value);
  H5Aclose(attr);
  H5Sclose(space);
}

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// One output's grids, as XDMF: the cells (3DCoRectMesh, z slowest) with cell-centred
// attributes, and one polyvertex grid per solid.
bool wanted(const Problem& pb, const std::string& name) {
  for (const auto& f : pb.input.output.fields)
    if (f == name) return true;
  return false;
}

std::string xdmf_grids(const Problem& pb, const std::string& h5, const std::vector<long>& particle_counts,
                       const std::string& indent) {
  const Grid& g = pb.patch().grid;
  std::ostringstream x;
  x.precision(17);
  const long nx = g.cells[0], ny = g.cells[1], nz = g.cells[2];
  if (pb.has_cells()) {
    x << indent << "<Grid Name=\"cells\" GridType=\"Uniform\">\n"
      << indent << "  <Time Value=\"" << pb.time << "\"/>\n"
      << indent << "  <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"" << nz + 1 << " " << ny + 1 << " "
      << nx + 1 << "\"/>\n"
      << indent << "  <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"
      << indent << "    <DataItem Dimensions=\"3\" Format=\"XML\">" << g.lower[2] << " " << g.lower[1] << " "
      << g.lower[0] << "</DataItem>\n"
      << indent << "    <DataItem Dimensions=\"3\" Format=\"XML\">" << g.spacing[2] << " " << g.spacing[1] << " "
      << g.spacing[0] << "</DataItem>\n"
      << indent << "  </Geometry>\n";
    auto attr = [&](const std::string& name, bool vector) {
      x << indent << "  <Attribute Name=\"" << name << "\" AttributeType=\"" << (vector ? "Vector" : "Scalar")
        << "\" Center=\"Cell\">\n"
        << indent << "    <DataItem Dimensions=\"" << nz << " " << ny << " " << nx << (vector ? " 3" : "")
        << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ":/cells/" << name
        << "</DataItem>\n"
        << indent << "  </Attribute>\n";
    };
    if (wanted(pb, "pressure")) attr("pressure", false);
    for (int m : pb.ice) {
      const std::string& name = pb.input.materials[m].name;
      for (const char* q : {"density", "temperature", "volume_fraction"})
        if (wanted(pb, q)) attr(std::string(q) + "_" + name, false);
      if (wanted(pb, "velocity")) attr("velocity_" + name, true);
    }
    x << indent << "</Grid>\n";
  }
  for (int s = 0; s < pb.solid_count(); ++s) {
    const std::string& name = pb.input.materials[pb.mpm[s]].name;
    const long n = particle_counts[s];
    x << indent << "<Grid Name=\"particles_" << name << "\" GridType=\"Uniform\">\n"
      << indent << "  <Time Value=\"" << pb.time << "\"/>\n"
      << indent << "  <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\"/>\n"
      << indent << "  <Geometry GeometryType=\"XYZ\">\n"
      << indent << "    <DataItem Dimensions=\"" << n << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
      << h5 << ":/particles/" << name << "/position</DataItem>\n"
      << indent << "  </Geometry>\n";
    for (const char* q : {"mass", "temperature", "velocity", "von_mises_stress", "plastic_strain", "stress"}) {
      const std::string key = std::string(q) == "von_mises_stress" || std::string(q) == "plastic_strain"
                                  ? q : "particle_" + std::string(q);
      if (!wanted(pb, key)) continue;
      const bool vector = std::string(q) == "velocity", tensor = std::string(q) == "stress";
      x << indent << "  <Attribute Name=\"" << q << "\" AttributeType=\""
        << (vector ? "Vector" : tensor ? "Tensor" : "Scalar") << "\" Center=\"Node\">\n"
        << indent << "    <DataItem Dimensions=\"" << n << (vector ? " 3" : tensor ? " 9" : "")
        << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ":/particles/" << name << "/" << q
        << "</DataItem>\n"
        << indent << "  </Attribute>\n";
    }
    x << indent << "</Grid>\n";
  }
  return x.str();
}

void write_text(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << text;
    if (!out.flush()) throw InvariantError("writing '" + tmp + "' failed");
  }
  std::rename(tmp.c_str(), path.c_str());
}

}  // namespace

FieldOutput::FieldOutput(const Problem&, const std::string& directory) : m_dir(directory) {}

std::string FieldOutput::write(const Problem& pb) {
  MPI_Comm comm = pb.decomposition->comm();
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  char name[64];
  std::snprintf(name, sizeof name, "fields_%06ld.h5", pb.step);
  const std::string path = m_dir + "/" + name;
  const std::string tmp = path + ".tmp";
  const Patch& p = pb.patch();
  std::vector<long> particle_counts(pb.solid_count(), 0);
  {
    ParallelH5File file(tmp, comm, true);
    if (file.id < 0) throw InvariantError("cannot create the output file '" + tmp + "'");
    write_attribute(file.id, "time", pb.time);
    write_attribute(file.id, "step", double(pb.step));
    if (pb.has_cells()) {
      hid_t group = H5Gcreate2(file.id, "cells", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      H5Gclose(group);
      const IndexBox own = p.owned_cells();
      const hsize_t ni = own.extent(0), nj = own.extent(1), nk = own.extent(2);
      const std::vector<hsize_t> global{hsize_t(p.grid.cells[2]), hsize_t(p.grid.cells[1]), hsize_t(p.grid.cells[0])};
      const std::vector<hsize_t> offset{hsize_t(p.lo[2]), hsize_t(p.lo[1]), hsize_t(p.lo[0])};
      const std::vector<hsize_t> count{nk, nj, ni};
      // z slowest, x fastest: the order XDMF's 3DCoRectMesh reads.
      auto gather = [&](auto value, int comps) {
        std::vector<double> out(ni * nj * nk * comps);
        std::size_t q = 0;
        for (int k = own.lo[2]; k < own.hi[2]; ++k)
          for (int j = own.lo[1]; j < own.hi[1]; ++j)
            for (int i = own.lo[0]; i < own.hi[0]; ++i)
              for (int c = 0; c < comps; ++c) out[q++] = value(i, j, k, c);
        return out;
      };
      const HostState st = host_state(pb);
      const auto &rho = st.rho, &temp = st.temp, &spv = st.sp_vol;
  const auto& press = st.press;
      const auto& vel = st.vel;
      if (wanted(pb, "pressure"))
        write_block(file.id, "/cells/pressure", global, offset, count,
                    gather([&](int i, int j, int k, int) { return press(i, j, k); }, 1));
      for (int m : pb.ice) {
        const std::string mat = pb.input.materials[m].name;
        if (wanted(pb, "density"))
          write_block(file.id, "/cells/density_" + mat, global, offset, count,
                      gather([&](int i, int j, int k, int) { return rho(m, i, j, k); }, 1));
        if (wanted(pb, "temperature"))
          write_block(file.id, "/cells/temperature_" + mat, global, offset, count,
                      gather([&](int i, int j, int k, int) { return temp(m, i, j, k); }, 1));
        if (wanted(pb, "volume_fraction"))
          write_block(file.id, "/cells/volume_fraction_" + mat, global, offset, count,
                      gather([&](int i, int j, int k, int) { return rho(m, i, j, k) * spv(m, i, j, k); }, 1));
        if (!wanted(pb, "velocity")) continue;
        std::vector<hsize_t> g3 = global, o3 = offset, c3 = count;
        g3.push_back(3);
        o3.push_back(0);
        c3.push_back(3);
        write_block(file.id, "/cells/velocity_" + mat, g3, o3, c3,
                    gather([&](int i, int j, int k, int c) { return vel[c](m, i, j, k); }, 3));
      }
    }
    if (pb.solid_count() > 0) {
      hid_t group = H5Gcreate2(file.id, "particles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      H5Gclose(group);
    }
    for (int s = 0; s < pb.solid_count(); ++s) {
      const std::string mat = pb.input.materials[pb.mpm[s]].name;
      const std::string base = "/particles/" + mat;
      hid_t group = H5Gcreate2(file.id, base.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      H5Gclose(group);
      const ParticleSet& ps = pb.particles[s];
      const long mine = long(ps.size());
      long before = 0, total = 0;
      MPI_Exscan(&mine, &before, 1, MPI_LONG, MPI_SUM, comm);
      if (rank == 0) before = 0;
      MPI_Allreduce(&mine, &total, 1, MPI_LONG, MPI_SUM, comm);
      particle_counts[s] = total;
      auto data = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
      auto column_of = [&](ParticleField first, int comps) {
        std::vector<double> out(std::size_t(mine) * comps);
        for (long q = 0; q < mine; ++q)
          for (int c = 0; c < comps; ++c) out[q * comps + c] = data(q, column(first) + c);
        return out;
      };
      const std::vector<hsize_t> g1{hsize_t(total)}, o1{hsize_t(before)}, c1{hsize_t(mine)};
      const std::vector<hsize_t> g3{hsize_t(total), 3}, o3{hsize_t(before), 0}, c3{hsize_t(mine), 3};
      write_block(file.id, base + "/position", g3, o3, c3, column_of(ParticleField::x, 3));
      if (wanted(pb, "particle_velocity"))
        write_block(file.id, base + "/velocity", g3, o3, c3, column_of(ParticleField::vx, 3));
      if (wanted(pb, "particle_mass"))
        write_block(file.id, base + "/mass", g1, o1, c1, column_of(ParticleField::mass, 1));
      if (wanted(pb, "particle_temperature"))
        write_block(file.id, base + "/temperature", g1, o1, c1, column_of(ParticleField::temperature, 1));
      if (wanted(pb, "plastic_strain"))
        write_block(file.id, base + "/plastic_strain", g1, o1, c1, column_of(ParticleField::plastic_strain, 1));
      if (wanted(pb, "particle_stress")) {
        const std::vector<hsize_t> g9{hsize_t(total), 9}, o9{hsize_t(before), 0}, c9{hsize_t(mine), 9};
        write_block(file.id, base + "/stress", g9, o9, c9, column_of(ParticleField::s00, 9));
      }
      if (wanted(pb, "von_mises_stress")) {
        std::vector<double> vm(mine);
        for (long q = 0; q < mine; ++q) vm[q] = std::sqrt(1.5) * load_tensor(data, q, ParticleField::s00).deviator().norm();
        write_block(file.id, base + "/von_mises_stress", g1, o1, c1, vm);
      }
    }
  }
  MPI_Barrier(comm);
  if (rank == 0) {
    std::rename(tmp.c_str(), path.c_str());
    const std::string head = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n";
    const std::string tail = "  </Domain>\n</Xdmf>\n";
    auto collection = [&](const std::string& grids, const std::string& indent) {
      return indent + "<Grid Name=\"output\" GridType=\"Collection\" CollectionType=\"Spatial\">\n" + grids +
             indent + "</Grid>\n";
    };
    m_written.push_back({name, pb.time, xdmf_grids(pb, name, particle_counts, "        ")});
    write_text(path.substr(0, path.size() - 3) + ".xdmf",
               head + collection(xdmf_grids(pb, name, particle_counts, "      "), "    ") + tail);
    // The time series: every output so far, each a spatial collection of its grids.
    std::ostringstream series;
    series << head << "    <Grid Name=\"series\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto& e : m_written) series << collection(e.grids, "      ");
    series << "    </Grid>\n" << tail;
    write_text(m_dir + "/fields.xdmf", series.str());
  }
  MPI_Barrier(comm);
  return path;
}

}  // namespace mpmice
