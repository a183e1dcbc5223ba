// Volumes in and out through ITK (patient): NIfTI, NRRD, MetaImage or a
// DICOM series read into softface's plain Volume with ITK's physical frame,
// and written back; every failure one message naming the file.

#include <softface/core/error.h>
#include <softface/patient/image_io.h>

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
      from_itk(const typename itk::Image<T, 3>::Pointer &image)
      {
        Volume<T>  volume;
        const auto size      = image->GetLargestPossibleRegion().GetSize();
        const auto spacing   = image->GetSpacing();
        const auto origin    = image->GetOrigin();
        const auto direction = image->GetDirection();
        for (unsigned int d = 0; d < 3; ++d)
          {
            volume.size[d]    = size[d];
            volume.spacing[d] = spacing[d];
            volume.origin[d]  = origin[d];
            for (unsigned int c = 0; c < 3; ++c)
              volume.direction[3 * d + c] = direction[d][c];
          }
        const T *data = image->GetBufferPointer();
        volume.values.assign(data, data + volume.n_voxels());
        return volume;
      }

      template <typename T>
      typename itk::Image<T, 3>::Pointer
      to_itk(const Volume<T> &volume)
      {
        using Image                         = itk::Image<T, 3>;
        auto                          image = Image::New();
        typename Image::SizeType      size;
        typename Image::SpacingType   spacing;
        typename Image::PointType     origin;
        typename Image::DirectionType direction;
        for (unsigned int d = 0; d < 3; ++d)
          {
            size[d]    = volume.size[d];
            spacing[d] = volume.spacing[d];
            origin[d]  = volume.origin[d];
            for (unsigned int c = 0; c < 3; ++c)
              direction[d][c] = volume.direction[3 * d + c];
          }
        image->SetRegions(size);
        image->SetSpacing(spacing);
        image->SetOrigin(origin);
        image->SetDirection(direction);
        image->Allocate();
        std::copy(volume.values.begin(),
                  volume.values.end(),
                  image->GetBufferPointer());
        return image;
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
