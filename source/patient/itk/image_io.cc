// Volumes in and out through ITK (patient): NIfTI, NRRD, MetaImage or a
// DICOM series read into softface's plain Volume with ITK's physical frame,
// and written back; every failure one message naming the file.

#include <softface/core/error.h>
#include <softface/patient/image_io.h>

#include "itk_volume.h"

#include <zlib.h>

#include <vector>

#include <itkGDCMImageIO.h>
#include <itkGDCMSeriesFileNames.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>
#include <itkImageIOFactory.h>
#include <itkImageSeriesReader.h>
#include <itkVersion.h>

#include <filesystem>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      // ITK reads a truncated or damaged .gz as a volume padded with
      // zeros; gzip's own checks (length and CRC) refuse it.
      void
      check_gzip(const std::string &filename)
      {
        gzFile file = gzopen(filename.c_str(), "rb");
        if (file == nullptr)
          throw Error("cannot be opened");
        std::vector<char> buffer(1 << 16);
        int               n;
        while ((n = gzread(file, buffer.data(), buffer.size())) > 0)
          ;
        int               code    = Z_OK;
        const std::string message = gzerror(file, &code);
        const int         closed  = gzclose_r(file);
        if (n < 0 || (code != Z_OK && code != Z_STREAM_END) || closed != Z_OK)
          throw Error("a truncated or damaged gzip file (" +
                      (message.empty() ? std::string("zlib error") : message) +
                      ")");
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
                // A DICOM series: the largest one in the folder.
                auto names = itk::GDCMSeriesFileNames::New();
                names->SetUseSeriesDetails(true);
                names->SetDirectory(filename);
                std::vector<std::string> files;
                for (const auto &uid : names->GetSeriesUIDs())
                  if (names->GetFileNames(uid).size() > files.size())
                    files = names->GetFileNames(uid);
                if (files.size() < 2)
                  throw Error("no DICOM series of two or more slices");
                auto reader = itk::ImageSeriesReader<Image>::New();
                reader->SetImageIO(itk::GDCMImageIO::New());
                reader->SetFileNames(files);
                reader->Update();
                return from_itk<T>(reader->GetOutput());
              }
            if (!std::filesystem::exists(filename))
              throw Error("no such file");
            if (filename.size() > 3 &&
                filename.compare(filename.size() - 3, 3, ".gz") == 0)
              check_gzip(filename);
            auto io = itk::ImageIOFactory::CreateImageIO(
              filename.c_str(), itk::CommonEnums::IOFileMode::ReadMode);
            if (!io)
              throw Error("not an image format ITK reads");
            io->SetFileName(filename);
            io->ReadImageInformation();
            // A single-file volume shorter than its voxels is truncated (ITK
            // would pad it); header and data in two files are ITK's to check.
            const auto extension = std::filesystem::path(filename).extension();
            if ((extension == ".nii" || extension == ".nrrd" ||
                 extension == ".mha") &&
                std::filesystem::file_size(filename) <
                  io->GetImageSizeInBytes())
              throw Error("truncated: it holds " +
                          std::to_string(std::filesystem::file_size(filename)) +
                          " bytes for " +
                          std::to_string(io->GetImageSizeInBytes()) +
                          " bytes of voxels");
            if (io->GetNumberOfDimensions() != 3 || io->GetDimensions(2) < 2)
              throw Error("not a 3D volume (" +
                          std::to_string(io->GetNumberOfDimensions()) +
                          " dimensions)");
            if (io->GetNumberOfComponents() != 1)
              throw Error("not a scalar volume (" +
                          std::to_string(io->GetNumberOfComponents()) +
                          " components per voxel)");
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
