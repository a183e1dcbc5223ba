// Dense surfaces of a segmented head (patient; Mollemans et al. 2007,
// Sec. 3.1): iso-surfaces of the smoothed CT by VTK's flying edges (the skin,
// the skull), and PLY/VTP files.

#include <softface/core/error.h>
#include <softface/patient/surface.h>

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCleanPolyData.h>
#include <vtkCommand.h>
#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPLYReader.h>
#include <vtkPLYWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataConnectivityFilter.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      std::string
      extension_of(const std::string &filename)
      {
        return std::filesystem::path(filename).extension().string();
      }

      vtkSmartPointer<vtkPolyData>
      to_vtk(const TriangleSurface &surface)
      {
        vtkNew<vtkPoints> points;
        points->SetDataTypeToDouble();
        points->SetNumberOfPoints(surface.points.size());
        for (std::size_t i = 0; i < surface.points.size(); ++i)
          points->SetPoint(i, surface.points[i].data());
        vtkNew<vtkCellArray> polys;
        for (const auto &t : surface.triangles)
          {
            const vtkIdType ids[3] = {t[0], t[1], t[2]};
            polys->InsertNextCell(3, ids);
          }
        auto data = vtkSmartPointer<vtkPolyData>::New();
        data->SetPoints(points);
        data->SetPolys(polys);
        return data;
      }

      TriangleSurface
      from_vtk(vtkPolyData *data, const std::string &source)
      {
        TriangleSurface surface;
        if (data->GetPoints() == nullptr)
          return surface;
        surface.points.resize(data->GetNumberOfPoints());
        for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
          data->GetPoint(i, surface.points[i].data());
        vtkCellArray     *polys = data->GetPolys();
        vtkNew<vtkIdList> ids;
        polys->InitTraversal();
        while (polys->GetNextCell(ids))
          {
            if (ids->GetNumberOfIds() != 3)
              throw Error("Surface '" + source + "': a polygon with " +
                          std::to_string(ids->GetNumberOfIds()) +
                          " corners; softface reads triangles only.");
            for (unsigned int c = 0; c < 3; ++c)
              if (ids->GetId(c) < 0 ||
                  ids->GetId(c) >= data->GetNumberOfPoints())
                throw Error("Surface '" + source +
                            "': a triangle names point " +
                            std::to_string(ids->GetId(c)) + " of " +
                            std::to_string(data->GetNumberOfPoints()) + ".");
            surface.triangles.push_back(
              {{static_cast<unsigned int>(ids->GetId(0)),
                static_cast<unsigned int>(ids->GetId(1)),
                static_cast<unsigned int>(ids->GetId(2))}});
          }
        return surface;
      }
      // VTK's readers report a file they cannot read as an error event (and
      // an error print), not an exception: turn it into one message.
      class ReaderErrors : public vtkCommand
      {
      public:
        static ReaderErrors *
        New()
        {
          return new ReaderErrors;
        }
        void
        Execute(vtkObject *, unsigned long, void *call_data) override
        {
          if (message.empty() && call_data != nullptr)
            message = static_cast<const char *>(call_data);
          failed = true;
        }
        bool        failed = false;
        std::string message;
      };

      // VTK's PLY reader trusts the header's counts (a hostile one crashes
      // it): the vertices must have x, y and z, and the file must be long
      // enough for them (3 bytes a vertex at the very least).
      void
      check_ply_header(const std::string &filename)
      {
        std::ifstream         in(filename, std::ios::binary);
        std::string           line, word;
        double                n_vertices = -1.;
        std::string           element;
        std::set<std::string> properties;
        while (std::getline(in, line) && line.rfind("end_header", 0) != 0)
          {
            std::istringstream words(line);
            words >> word;
            if (word == "element")
              {
                words >> element;
                if (element == "vertex")
                  words >> n_vertices;
              }
            else if (word == "property" && element == "vertex")
              {
                std::string last;
                while (words >> word)
                  last = word;
                properties.insert(last);
              }
          }
        const auto size = std::filesystem::file_size(filename);
        if (!in || n_vertices < 0. || !properties.count("x") ||
            !properties.count("y") || !properties.count("z") ||
            3. * n_vertices > double(size))
          throw Error("Surface '" + filename +
                      "' cannot be read: not a PLY file of vertices with x, y, "
                      "z, or shorter than its header says.");
      }

      template <typename Reader>
      vtkSmartPointer<vtkPolyData>
      read_with(const std::string &filename)
      {
        vtkNew<Reader>       reader;
        vtkNew<ReaderErrors> errors;
        reader->AddObserver(vtkCommand::ErrorEvent, errors);
        reader->AddObserver(vtkCommand::WarningEvent, errors);
        reader->SetFileName(filename.c_str());
        reader->Update();
        if (errors->failed)
          {
            // VTK's message ends with its own newline.
            std::string m = errors->message;
            while (!m.empty() && (m.back() == '\n' || m.back() == ' '))
              m.pop_back();
            throw Error("Surface '" + filename + "' cannot be read: " + m);
          }
        return reader->GetOutput();
      }
    } // namespace

    double
    TriangleSurface::area() const
    {
      double a = 0.;
      for (const auto &t : triangles)
        {
          const Vec3  &p = points[t[0]], &q = points[t[1]], &r = points[t[2]];
          const double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
          const double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
          const double c[3] = {u[1] * v[2] - u[2] * v[1],
                               u[2] * v[0] - u[0] * v[2],
                               u[0] * v[1] - u[1] * v[0]};
          a += 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        }
      return a;
    }

    TriangleSurface
    iso_surface(const Volume<float> &volume,
                const double         value,
                const bool           largest_piece,
                const unsigned int   min_points)
    {
      // VTK sees the grid in index space scaled by the spacing; the origin
      // and the direction cosines are applied to the points afterwards.
      vtkNew<vtkImageData> image;
      image->SetDimensions(volume.size[0], volume.size[1], volume.size[2]);
      image->SetSpacing(volume.spacing[0],
                        volume.spacing[1],
                        volume.spacing[2]);
      image->SetOrigin(0., 0., 0.);
      vtkNew<vtkFloatArray> scalars;
      scalars->SetNumberOfTuples(volume.n_voxels());
      std::copy(volume.values.begin(),
                volume.values.end(),
                scalars->GetPointer(0));
      image->GetPointData()->SetScalars(scalars);

      vtkNew<vtkFlyingEdges3D> contour;
      contour->SetInputData(image);
      contour->SetValue(0, value);
      contour->ComputeNormalsOff();
      contour->ComputeGradientsOff();
      contour->ComputeScalarsOff();

      vtkNew<vtkPolyDataConnectivityFilter> pieces;
      pieces->SetInputConnection(contour->GetOutputPort());
      if (largest_piece)
        pieces->SetExtractionModeToLargestRegion();
      else
        pieces->SetExtractionModeToAllRegions();
      pieces->ColorRegionsOn();
      pieces->Update();

      vtkSmartPointer<vtkPolyData> result = pieces->GetOutput();
      if (!largest_piece)
        {
          // Keep the pieces with enough points.
          vtkIdTypeArray *sizes = pieces->GetRegionSizes();
          vtkNew<vtkPolyDataConnectivityFilter> keep;
          keep->SetInputConnection(contour->GetOutputPort());
          keep->SetExtractionModeToSpecifiedRegions();
          for (vtkIdType r = 0; r < sizes->GetNumberOfTuples(); ++r)
            if (sizes->GetValue(r) >= vtkIdType(min_points))
              keep->AddSpecifiedRegion(r);
          keep->Update();
          result = keep->GetOutput();
        }
      vtkNew<vtkCleanPolyData> clean;
      clean->SetInputData(result);
      clean->PointMergingOff();
      clean->Update();

      TriangleSurface surface = from_vtk(clean->GetOutput(), "iso-surface");
      for (Vec3 &p : surface.points)
        p = volume.point(p[0] / volume.spacing[0],
                         p[1] / volume.spacing[1],
                         p[2] / volume.spacing[2]);
      // A left-handed frame mirrors the triangles: keep their orientation.
      const auto  &D   = volume.direction;
      const double det = D[0] * (D[4] * D[8] - D[5] * D[7]) -
                         D[1] * (D[3] * D[8] - D[5] * D[6]) +
                         D[2] * (D[3] * D[7] - D[4] * D[6]);
      if (det < 0.)
        for (auto &t : surface.triangles)
          std::swap(t[1], t[2]);
      return surface;
    }

    void
    write_surface(const TriangleSurface &surface, const std::string &filename)
    {
      write_surface(surface, filename, {});
    }

    void
    write_surface(const TriangleSurface         &surface,
                  const std::string             &filename,
                  const std::vector<PointField> &fields)
    {
      const auto data = to_vtk(surface);
      for (const PointField &field : fields)
        {
          if (field.values.size() != field.components * surface.points.size())
            throw Error("Surface '" + filename + "': field '" + field.name +
                        "' does not have one value per point.");
          vtkNew<vtkFloatArray> array;
          array->SetName(field.name.c_str());
          array->SetNumberOfComponents(field.components);
          array->SetNumberOfTuples(surface.points.size());
          for (unsigned int i = 0; i < field.values.size(); ++i)
            array->SetValue(i, field.values[i]);
          data->GetPointData()->AddArray(array);
        }
      const auto extension = extension_of(filename);
      int        ok        = 0;
      if (extension == ".ply")
        {
          vtkNew<vtkPLYWriter> writer;
          writer->SetFileName(filename.c_str());
          writer->SetFileTypeToBinary();
          writer->SetInputData(data);
          ok = writer->Write();
        }
      else if (extension == ".vtp")
        {
          vtkNew<vtkXMLPolyDataWriter> writer;
          writer->SetFileName(filename.c_str());
          writer->SetDataModeToBinary();
          writer->SetInputData(data);
          ok = writer->Write();
        }
      else
        throw Error("Surface '" + filename +
                    "': unknown format (softface writes .ply and .vtp).");
      if (ok != 1)
        throw Error("Cannot write '" + filename + "'.");
    }

    TriangleSurface
    read_surface(const std::string &filename)
    {
      if (!std::filesystem::exists(filename))
        throw Error("Cannot open surface '" + filename + "'.");
      const auto                   extension = extension_of(filename);
      vtkSmartPointer<vtkPolyData> data;
      if (extension == ".ply")
        {
          check_ply_header(filename);
          data = read_with<vtkPLYReader>(filename);
        }
      else if (extension == ".vtp")
        data = read_with<vtkXMLPolyDataReader>(filename);
      else
        throw Error("Surface '" + filename +
                    "': unknown format (softface reads .ply and .vtp).");
      if (data == nullptr || data->GetNumberOfPoints() == 0)
        throw Error("Surface '" + filename + "' holds no points.");
      return from_vtk(data, filename);
    }
  } // namespace Patient
} // namespace softface
