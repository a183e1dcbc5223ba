// Volumes in and out through ITK (patient): NIfTI, NRRD, MetaImage or a
// DICOM series read into softface's plain Volume with ITK's physical frame,
// and written back; every failure one message naming the file.

#include <softface/core/error.h>
#include <softface/patient/image_io.h>

#include "itk_volume.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include <itkGDCMImageIO.h>
#include <itkGDCMSeriesFileNames.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>
#include <itkImageIOFactory.h>
#include <itkImageSeriesReader.h>
#include <itkMetaDataObject.h>
#include <itkVersion.h>

#include <filesystem>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      // What no scanner writes: refused before a voxel is allocated. A head
      // CT has well under 200 million voxels; past 2^31 the readers' int
      // counters overflow and the buffers alone need many GB.
      constexpr std::uint64_t max_voxels  = std::uint64_t(1) << 31;
      constexpr double        min_spacing = 0.001; // mm
      constexpr double        max_spacing = 100;   // mm

      std::string
      number(const double x)
      {
        std::ostringstream s;
        s << x;
        return s.str();
      }

      bool
      ends_with(const std::string &s, const std::string &end)
      {
        return s.size() >= end.size() &&
               s.compare(s.size() - end.size(), end.size(), end) == 0;
      }

      // ITK reads a truncated or damaged .gz as a volume padded with
      // zeros; gzip's own checks (length and CRC) refuse it. Returns the
      // number of bytes the stream decompresses to, or, once past @p limit
      // (what the header declares), a number past it without reading on:
      // a stream that inflates far beyond its header (a gzip bomb) costs
      // no more than the volume it claims to be.
      std::uint64_t
      check_gzip(const std::string  &filename,
                 const std::uint64_t limit = std::uint64_t(-1))
      {
        gzFile file = gzopen(filename.c_str(), "rb");
        if (file == nullptr)
          throw Error("cannot be opened");
        std::vector<char> buffer(1 << 16);
        std::uint64_t     length = 0;
        int               n;
        while ((n = gzread(file, buffer.data(), buffer.size())) > 0)
          if ((length += n) > limit)
            {
              gzclose_r(file);
              return length;
            }
        int               code    = Z_OK;
        const std::string message = gzerror(file, &code);
        const int         closed  = gzclose_r(file);
        if (n < 0 || (code != Z_OK && code != Z_STREAM_END) || closed != Z_OK)
          throw Error("a truncated or damaged gzip file (" +
                      (message.empty() ? std::string("zlib error") : message) +
                      ")");
        return length;
      }

      // The bytes a zlib or gzip stream from @p offset of the file inflates
      // to (MetaImage's CompressedData, NRRD's gzip encoding).
      std::uint64_t
      inflated_length(const std::string &filename, const std::uint64_t offset)
      {
        std::ifstream in(filename, std::ios::binary);
        in.seekg(offset);
        z_stream z{};
        if (!in || inflateInit2(&z, 15 + 32) != Z_OK)
          throw Error("cannot be opened");
        std::vector<unsigned char> input(1 << 16), output(1 << 16);
        std::uint64_t              length = 0;
        int                        code   = Z_OK;
        while (code != Z_STREAM_END)
          {
            if (z.avail_in == 0)
              {
                in.read(reinterpret_cast<char *>(input.data()), input.size());
                z.next_in  = input.data();
                z.avail_in = static_cast<unsigned int>(in.gcount());
                if (z.avail_in == 0)
                  break;
              }
            z.next_out  = output.data();
            z.avail_out = output.size();
            code        = inflate(&z, Z_NO_FLUSH);
            length += output.size() - z.avail_out;
            if (code != Z_OK && code != Z_STREAM_END)
              break;
          }
        inflateEnd(&z);
        if (code != Z_STREAM_END)
          throw Error("its compressed voxel data is truncated or damaged "
                      "(after " +
                      std::to_string(length) + " bytes)");
        return length;
      }

      // The bytes of voxel data a single-file volume holds, as against what
      // its header declares: ITK pads a short one with zeros. -1 where the
      // data is elsewhere or in an encoding not counted here (ITK's own
      // checks then hold).
      struct Payload
      {
        std::int64_t held     = -1;
        std::int64_t declared = -1;
        // NIfTI float voxels: their size in bytes (4 or 8, else 0), byte
        // order and offset, for the scan for NaN.
        unsigned int  float_bytes = 0;
        bool          swap        = false;
        std::uint64_t offset      = 0;
        // Whether the data must end where the voxels do (NIfTI).
        bool exact = false;
      };

      std::string
      not_finite_message(const std::size_t                 n_not_finite,
                         const std::size_t                 first,
                         const std::array<std::size_t, 3> &size)
      {
        return std::to_string(n_not_finite) + " of its " +
               std::to_string(size[0] * size[1] * size[2]) +
               " voxels are not finite numbers (NaN or infinite), the first "
               "at voxel (" +
               std::to_string(first % size[0]) + ", " +
               std::to_string(first / size[0] % size[1]) + ", " +
               std::to_string(first / size[0] / size[1]) + ")";
      }

      std::string
      read_head(const std::string &filename, const std::size_t n)
      {
        // gzread reads an uncompressed file as it is.
        gzFile file = gzopen(filename.c_str(), "rb");
        if (file == nullptr)
          throw Error("cannot be opened");
        std::string head(n, '\0');
        const int   got = gzread(file, head.data(), n);
        gzclose_r(file);
        head.resize(got > 0 ? got : 0);
        return head;
      }

      template <typename Number>
      Number
      field(const std::string &header, const std::size_t at, const bool swap)
      {
        unsigned char bytes[sizeof(Number)];
        std::memcpy(bytes, header.data() + at, sizeof(Number));
        if (swap)
          std::reverse(bytes, bytes + sizeof(Number));
        Number x;
        std::memcpy(&x, bytes, sizeof(Number));
        return x;
      }

      // NIfTI-1: ITK's NiftiImageIO keeps neither the data offset nor the
      // on-disk voxel type (it reports float when the file rescales), and
      // the NIfTI library replaces a zero or non-finite voxel size with 1 and
      // reads a negative dimension as 1: those are checked in the header.
      Payload
      check_nifti(const std::string &filename, const std::uint64_t stream_bytes)
      {
        const std::string h = read_head(filename, 348);
        if (h.size() < 348)
          return {}; // not NIfTI-1: ITK's to judge
        bool swap = false;
        if (field<std::int32_t>(h, 0, false) != 348)
          {
            swap = true;
            if (field<std::int32_t>(h, 0, true) != 348)
              return {}; // not NIfTI-1: ITK's to judge
          }
        const int n_dims = field<std::int16_t>(h, 40, swap);
        if (n_dims < 1 || n_dims > 7)
          throw Error("its NIfTI header declares " + std::to_string(n_dims) +
                      " dimensions");
        std::uint64_t n_voxels = 1;
        for (int d = 1; d <= n_dims; ++d)
          {
            const int n = field<std::int16_t>(h, 40 + 2 * d, swap);
            if (n < 1)
              throw Error("its size along axis " + std::to_string(d - 1) +
                          " is " + std::to_string(n) + " voxels");
            // At most 32767^7: saturated rather than wrapped around.
            n_voxels = n_voxels > (std::uint64_t(1) << 48) ?
                         n_voxels :
                         n_voxels * static_cast<std::uint64_t>(n);
          }
        const int qform_code = field<std::int16_t>(h, 252, swap);
        const int sform_code = field<std::int16_t>(h, 254, swap);
        // pixdim is the voxel size unless an sform alone places the grid.
        if (qform_code > 0 || sform_code <= 0)
          for (int d = 1; d <= std::min(n_dims, 3); ++d)
            {
              const double s = field<float>(h, 76 + 4 * d, swap);
              if (!(std::isfinite(s) && s >= min_spacing && s <= max_spacing))
                throw Error("its voxel size along axis " +
                            std::to_string(d - 1) + " is " + number(s) +
                            " mm (expected " + number(min_spacing) + " to " +
                            number(max_spacing) + " mm)");
            }
        // The NIfTI library reads a non-finite quaternion, offset or sform
        // entry as 0, and ITK aborts on an sform whose singular values
        // overflow.
        const auto finite = [&](const std::size_t from, const std::size_t to) {
          for (std::size_t at = from; at < to; at += 4)
            if (!(std::abs(field<float>(h, at, swap)) <= 1e6f))
              return false;
          return true;
        };
        if ((qform_code > 0 && !finite(256, 280)) ||
            (sform_code > 0 && !finite(280, 328)))
          throw Error(
            "its origin or axis directions (the NIfTI header's " +
            std::string(qform_code > 0 && !finite(256, 280) ? "qform" :
                                                              "sform") +
            ") hold a value that is not a number, infinite or over 1e6");
        if (h.compare(344, 3, "n+1") != 0)
          return {}; // header and data in two files: ITK's to check
        const int datatype = field<std::int16_t>(h, 70, swap);
        // Bytes per voxel as the NIfTI library takes them: from the
        // datatype code, not from bitpix.
        std::uint64_t bytes = 0;
        switch (datatype)
          {
            case 2:   // uint8
            case 256: // int8
              bytes = 1;
              break;
            case 4:   // int16
            case 512: // uint16
              bytes = 2;
              break;
            case 128: // RGB
              bytes = 3;
              break;
            case 8:    // int32
            case 16:   // float32
            case 768:  // uint32
            case 2304: // RGBA
              bytes = 4;
              break;
            case 32:   // complex64
            case 64:   // float64
            case 1024: // int64
            case 1280: // uint64
              bytes = 8;
              break;
            case 1536: // float128
            case 1792: // complex128
              bytes = 16;
              break;
            case 2048: // complex256
              bytes = 32;
              break;
            default:
              return {}; // ITK's to refuse
          }
        // The NIfTI library reads a data offset under the header's 348
        // bytes (or not a number) as 348.
        double offset = field<float>(h, 108, swap);
        if (!(offset >= 348))
          offset = 348;
        Payload p;
        p.declared    = n_voxels * bytes;
        p.float_bytes = datatype == 16 ? 4 : datatype == 64 ? 8 : 0;
        p.swap        = swap;
        p.offset      = static_cast<std::uint64_t>(offset);
        p.exact       = true;
        p.held        = offset < static_cast<double>(stream_bytes) ?
                          stream_bytes - static_cast<std::uint64_t>(offset) :
                          0;
        return p;
      }

      // The NIfTI library reads NaN and infinite float voxels as 0: they
      // are counted in the file itself.
      void
      check_nifti_floats(const std::string                &filename,
                         const Payload                    &payload,
                         const std::array<std::size_t, 3> &size)
      {
        gzFile file = gzopen(filename.c_str(), "rb");
        if (file == nullptr)
          throw Error("cannot be opened");
        const std::uint64_t n_values = size[0] * size[1] * size[2];
        std::vector<char>   buffer(std::size_t(1) << 16);
        std::uint64_t       skip = payload.offset, index = 0;
        std::size_t         n_not_finite = 0, first = 0, kept = 0;
        int                 n;
        while (index < n_values &&
               (n = gzread(file, buffer.data() + kept, buffer.size() - kept)) >
                 0)
          {
            std::size_t available = kept + n, at = 0;
            if (skip > 0)
              {
                at = std::min<std::uint64_t>(skip, available);
                skip -= at;
              }
            for (; at + payload.float_bytes <= available && index < n_values;
                 at += payload.float_bytes, ++index)
              {
                const std::string value(buffer.data() + at,
                                        payload.float_bytes);
                const double      x =
                  payload.float_bytes == 4 ?
                         double(field<float>(value, 0, payload.swap)) :
                         field<double>(value, 0, payload.swap);
                if (!std::isfinite(x) && n_not_finite++ == 0)
                  first = index;
              }
            kept = available - at;
            std::memmove(buffer.data(), buffer.data() + at, kept);
          }
        gzclose_r(file);
        if (n_not_finite > 0)
          throw Error(not_finite_message(n_not_finite, first, size));
      }

      // MetaImage (.mha, data in the file) and NRRD (data in the file,
      // raw or gzip): the text header ends at MetaImage's ElementDataFile
      // line or at NRRD's first empty line.
      Payload
      check_text_header(const std::string      &filename,
                        const bool              nrrd,
                        const itk::ImageIOBase &io)
      {
        std::ifstream in(filename, std::ios::binary);
        std::string   line;
        bool          compressed = false, ended = false;
        while (std::getline(in, line))
          {
            if (!line.empty() && line.back() == '\r')
              line.pop_back();
            const auto  colon = line.find(nrrd ? ':' : '=');
            std::string key   = line.substr(0, colon);
            std::string value =
              colon == std::string::npos ? "" : line.substr(colon + 1);
            const auto trim = [](std::string &s) {
              s.erase(0, s.find_first_not_of(" \t"));
              s.erase(s.find_last_not_of(" \t") + 1);
            };
            trim(key);
            trim(value);
            if (nrrd)
              {
                if (line.empty())
                  {
                    ended = true;
                    break;
                  }
                if (key == "data file" || key == "datafile" ||
                    key == "byte skip" || key == "byteskip" ||
                    key == "line skip" || key == "lineskip")
                  return {};
                if (key == "encoding")
                  {
                    if (value == "gzip" || value == "gz")
                      compressed = true;
                    else if (value != "raw")
                      return {};
                  }
              }
            else
              {
                if (key == "CompressedData")
                  compressed = value == "True" || value == "true";
                if (key == "HeaderSize")
                  return {};
                if (key == "ElementDataFile")
                  {
                    if (value != "LOCAL" && value != "Local" &&
                        value != "local")
                      return {};
                    ended = true;
                    break;
                  }
              }
          }
        if (!ended || !in)
          return {};
        const std::uint64_t offset = in.tellg();
        Payload             p;
        p.declared = io.GetImageSizeInBytes();
        p.held     = compressed ? inflated_length(filename, offset) :
                                  std::filesystem::file_size(filename) - offset;
        return p;
      }

      // The grid ITK read from the header: a size, voxel size and frame
      // that no scan has, refused before the voxels are allocated.
      void
      check_grid(const itk::ImageIOBase &io)
      {
        std::uint64_t n_voxels = 1;
        for (unsigned int d = 0; d < 3; ++d)
          {
            if (io.GetDimensions(d) == 0)
              throw Error("its size along axis " + std::to_string(d) +
                          " is 0 voxels");
            n_voxels *= io.GetDimensions(d);
          }
        if (n_voxels > max_voxels)
          throw Error(
            "its header declares " + std::to_string(io.GetDimensions(0)) +
            " x " + std::to_string(io.GetDimensions(1)) + " x " +
            std::to_string(io.GetDimensions(2)) + " voxels, more than " +
            std::to_string(max_voxels) + " (no CT has that many)");
        for (unsigned int d = 0; d < 3; ++d)
          {
            const double s = io.GetSpacing(d);
            if (!(std::isfinite(s) && s >= min_spacing && s <= max_spacing))
              throw Error("its voxel size along axis " + std::to_string(d) +
                          " is " + number(s) + " mm (expected " +
                          number(min_spacing) + " to " + number(max_spacing) +
                          " mm)");
            if (!std::isfinite(io.GetOrigin(d)))
              throw Error("its origin is not a finite point");
            for (unsigned int c = 0; c < 3; ++c)
              if (!std::isfinite(io.GetDirection(d)[c]))
                throw Error("its axis directions are not finite numbers");
          }
      }

      // Voxels of a float file: NaN or infinite values have no Hounsfield
      // unit or label (converted, they would become arbitrary integers),
      // nor have values past the range of the voxel type softface keeps.
      template <typename T, typename S>
      Volume<T>
      converted(const typename itk::Image<S, 3>::Pointer &image)
      {
        const Volume<S> source = from_itk<S>(image);
        Volume<T>       volume;
        volume.size              = source.size;
        volume.spacing           = source.spacing;
        volume.origin            = source.origin;
        volume.direction         = source.direction;
        std::size_t n_not_finite = 0, n_outside = 0, first = 0;
        const S     low  = static_cast<S>(std::numeric_limits<T>::lowest());
        const S     high = static_cast<S>(std::numeric_limits<T>::max());
        for (std::size_t i = 0; i < source.values.size(); ++i)
          {
            const S x = source.values[i];
            if (!std::isfinite(x))
              {
                if (n_not_finite++ == 0)
                  first = i;
              }
            else if (x < low || x > high)
              ++n_outside;
          }
        if (n_not_finite > 0)
          throw Error(not_finite_message(n_not_finite, first, source.size));
        if (n_outside > 0)
          throw Error(std::to_string(n_outside) +
                      " of its voxel values lie "
                      "outside the range " +
                      number(low) + " to " + number(high) +
                      " that softface keeps");
        volume.values.resize(source.values.size());
        // As ITK converts: toward zero.
        for (std::size_t i = 0; i < source.values.size(); ++i)
          volume.values[i] = static_cast<T>(source.values[i]);
        return volume;
      }

      template <typename T, typename S>
      Volume<T>
      read_file(const std::string &filename)
      {
        auto reader = itk::ImageFileReader<itk::Image<S, 3>>::New();
        reader->SetFileName(filename);
        reader->Update();
        return converted<T, S>(reader->GetOutput());
      }

      template <typename T>
      Volume<T>
      read(const std::string &filename)
      {
        using Image = itk::Image<T, 3>;
        try
          {
            if (std::filesystem::is_directory(filename))
              {
                // A DICOM series: the one of the most slices in the folder
                // (a scout or localiser beside a scan is a series of its
                // own, told apart by its SeriesInstanceUID, or by its size,
                // slice thickness or series number). GDCM orders the slices
                // by ImagePositionPatient along the normal of
                // ImageOrientationPatient, not by file name or
                // InstanceNumber; ITK takes the frame from both, so an
                // oblique series keeps its own, without resampling.
                auto names = itk::GDCMSeriesFileNames::New();
                names->SetUseSeriesDetails(true);
                names->SetDirectory(filename);
                std::vector<std::string> files;
                for (const auto &uid : names->GetSeriesUIDs())
                  if (names->GetFileNames(uid).size() > files.size())
                    files = names->GetFileNames(uid);
                if (files.size() < 2)
                  throw Error("no DICOM series of two or more slices");
                // GDCM applies RescaleSlope and RescaleIntercept; read as
                // float, the values are checked like a float file's before
                // they become integers (a stored value the rescale takes
                // past 16 bits would otherwise wrap around).
                auto reader =
                  itk::ImageSeriesReader<itk::Image<float, 3>>::New();
                reader->SetImageIO(itk::GDCMImageIO::New());
                reader->SetFileNames(files);
                // The reader stacks the slices at one spacing and records
                // the largest deviation of a gap between neighbours from it:
                // a missing slice or uneven spacing is refused below, not
                // warned about on the console.
                reader->SetSpacingWarningRelThreshold(1e30);
                reader->Update();
                auto   image     = reader->GetOutput();
                double deviation = 0;
                if (itk::ExposeMetaData<double>(
                      image->GetMetaDataDictionary(),
                      "ITK_non_uniform_sampling_deviation",
                      deviation) &&
                    deviation > 0.01 * image->GetSpacing()[2])
                  throw Error(
                    "its " + std::to_string(files.size()) +
                    " slices are not evenly spaced (a slice missing, or "
                    "uneven spacing): the gap between neighbours differs "
                    "by up to " +
                    number(deviation) + " mm from the slice spacing of " +
                    number(image->GetSpacing()[2]) + " mm");
                // The reader keeps the first slice's directions and stacks
                // the slices along the normal of its rows and columns, at
                // the distance from the first slice's position to the
                // last's over the number of gaps. Positions that go another
                // way (a tilted gantry shears the slices along the table)
                // would be stacked as if they did not: the anatomy slanted
                // and stretched by 1 / cos(tilt). Refused.
                {
                  auto last = itk::GDCMImageIO::New();
                  last->SetFileName(files.back());
                  last->ReadImageInformation();
                  const auto &D     = image->GetDirection();
                  double      along = 0, across = 0;
                  for (unsigned int r = 0; r < 3; ++r)
                    along +=
                      (last->GetOrigin(r) - image->GetOrigin()[r]) * D[r][2];
                  for (unsigned int r = 0; r < 3; ++r)
                    across +=
                      std::pow(last->GetOrigin(r) - image->GetOrigin()[r] -
                                 along * D[r][2],
                               2);
                  across = std::sqrt(across);
                  if (!(along > 0 && across <= 0.01 * along))
                    throw Error(
                      "its slices are not stacked along the normal of their "
                      "rows and columns (ImageOrientationPatient): from the "
                      "first slice to the last, ImagePositionPatient moves " +
                      number(along) + " mm along the normal and " +
                      number(across) + " mm across it (" +
                      number(std::atan2(across, along) * 180 / M_PI) +
                      " degrees, as from a tilted gantry), a grid softface "
                      "does not resample");
                }
                for (unsigned int d = 0; d < 3; ++d)
                  {
                    const double s = image->GetSpacing()[d];
                    if (!(std::isfinite(s) && s >= min_spacing &&
                          s <= max_spacing))
                      throw Error("its voxel size along axis " +
                                  std::to_string(d) + " is " + number(s) +
                                  " mm (expected " + number(min_spacing) +
                                  " to " + number(max_spacing) + " mm)");
                  }
                return converted<T, float>(image);
              }
            if (!std::filesystem::exists(filename))
              throw Error("no such file");
            std::uint64_t stream_bytes = 0;
            const bool    gz           = ends_with(filename, ".gz");
            // Whether the count of a stream stopped past what its header
            // declares (check_gzip()): it holds at least that much.
            bool stream_cut = false;
            if (gz)
              {
                std::uint64_t limit = std::uint64_t(-1);
                if (ends_with(filename, ".nii.gz"))
                  if (const Payload header = check_nifti(filename, 0);
                      header.declared >= 0)
                    limit = header.offset + header.declared;
                stream_bytes = check_gzip(filename, limit);
                stream_cut   = stream_bytes > limit;
              }
            else if (std::filesystem::is_regular_file(filename))
              stream_bytes = std::filesystem::file_size(filename);
            auto io = itk::ImageIOFactory::CreateImageIO(
              filename.c_str(), itk::CommonEnums::IOFileMode::ReadMode);
            if (!io)
              throw Error("not an image format ITK reads");
            // Before ITK reads the header: ITK aborts the process on a
            // non-finite NIfTI sform.
            Payload payload;
            if (ends_with(filename, ".nii") || ends_with(filename, ".nii.gz"))
              payload = check_nifti(filename, stream_bytes);
            io->SetFileName(filename);
            io->ReadImageInformation();
            if (io->GetNumberOfDimensions() == 3 && io->GetDimensions(2) == 1)
              throw Error("a single slice, not a 3D volume");
            if (io->GetNumberOfDimensions() != 3 || io->GetDimensions(2) < 2)
              throw Error("not a 3D volume (" +
                          std::to_string(io->GetNumberOfDimensions()) +
                          " dimensions)");
            if (io->GetNumberOfComponents() != 1)
              throw Error("not a scalar volume (" +
                          std::to_string(io->GetNumberOfComponents()) +
                          " components per voxel)");
            check_grid(*io);
            // A single-file volume shorter than its voxels is truncated (ITK
            // would pad it); header and data in two files are ITK's to check.
            if (ends_with(filename, ".mha") || ends_with(filename, ".nrrd"))
              payload =
                check_text_header(filename, ends_with(filename, ".nrrd"), *io);
            if (payload.held >= 0 && payload.held < payload.declared)
              throw Error("truncated: it holds " +
                          std::to_string(payload.held) +
                          " bytes of voxel data where its header declares " +
                          std::to_string(payload.declared) + " (" +
                          std::to_string(io->GetDimensions(0)) + " x " +
                          std::to_string(io->GetDimensions(1)) + " x " +
                          std::to_string(io->GetDimensions(2)) + " voxels)");
            // Nothing follows a NIfTI volume's voxels: more data than the
            // header declares means a wrong size or data type in the header,
            // which ITK would read as a sheared or garbled volume.
            if (payload.exact && payload.held > payload.declared)
              throw Error(std::string("it holds ") +
                          (stream_cut ? "at least " : "") +
                          std::to_string(payload.held) +
                          " bytes of voxel data where its header declares " +
                          std::to_string(payload.declared) + " (" +
                          std::to_string(io->GetDimensions(0)) + " x " +
                          std::to_string(io->GetDimensions(1)) + " x " +
                          std::to_string(io->GetDimensions(2)) +
                          " voxels): the header's size or data type does not "
                          "match its data");
            if (payload.float_bytes > 0)
              check_nifti_floats(filename,
                                 payload,
                                 {{io->GetDimensions(0),
                                   io->GetDimensions(1),
                                   io->GetDimensions(2)}});
            // Float voxels are read as they are and checked before they
            // become integers.
            const auto type = io->GetComponentType();
            if (type == itk::IOComponentEnum::FLOAT)
              return read_file<T, float>(filename);
            if (type == itk::IOComponentEnum::DOUBLE)
              return read_file<T, double>(filename);
            auto reader = itk::ImageFileReader<Image>::New();
            reader->SetFileName(filename);
            reader->Update();
            return from_itk<T>(reader->GetOutput());
          }
        catch (const Error &e)
          {
            throw Error("Cannot read volume '" + filename + "': " + e.what() +
                        ".");
          }
        catch (const itk::ExceptionObject &e)
          {
            throw Error("Cannot read volume '" + filename +
                        "': " + e.GetDescription());
          }
      }

      template <typename T>
      void
      write(const Volume<T> &volume, const std::string &filename)
      {
        try
          {
            auto writer = itk::ImageFileWriter<itk::Image<T, 3>>::New();
            writer->SetFileName(filename);
            writer->SetInput(to_itk(volume));
            writer->UseCompressionOn();
            writer->Update();
          }
        catch (const itk::ExceptionObject &e)
          {
            throw Error("Cannot write volume '" + filename +
                        "': " + e.GetDescription());
          }
      }
    } // namespace

    CTVolume
    read_ct(const std::string &filename)
    {
      return read<std::int16_t>(filename);
    }

    LabelVolume
    read_labels(const std::string &filename)
    {
      return read<std::uint8_t>(filename);
    }

    void
    write_volume(const CTVolume &volume, const std::string &filename)
    {
      write(volume, filename);
    }

    void
    write_volume(const LabelVolume &volume, const std::string &filename)
    {
      write(volume, filename);
    }

    std::string
    itk_version()
    {
      return itk::Version::GetITKVersion();
    }
  } // namespace Patient
} // namespace softface
