// Volumes in and out through ITK (patient): NIfTI, NRRD, MetaImage or a
// DICOM series read into softface's plain Volume with ITK's physical frame,
// and written back; every failure one message naming the file.

#include <softface/core/error.h>
#include <softface/patient/image_io.h>

#include "itk_volume.h"

#include <itkGDCMImageIO.h>
#include <itkGDCMSeriesFileNames.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>
#include <itkImageIOFactory.h>
#include <itkImageSeriesReader.h>

#include <filesystem>

namespace softface
{
  namespace Patient
  {
    namespace
    {
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
            auto io = itk::ImageIOFactory::CreateImageIO(
              filename.c_str(), itk::CommonEnums::IOFileMode::ReadMode);
            if (!io)
              throw Error("not an image format ITK reads");
            io->SetFileName(filename);
            io->ReadImageInformation();
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
  } // namespace Patient
} // namespace softface
