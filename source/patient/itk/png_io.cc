// PNG pictures through ITK (the preview): softface's plain RGB picture
// copied into an itk::Image of RGB pixels and written by PNGImageIO, named
// directly so that no image IO factory needs to be registered.

#include <softface/core/error.h>
#include <softface/patient/png_io.h>

#include <algorithm>

#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>
#include <itkPNGImageIO.h>
#include <itkRGBPixel.h>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      using Pixel    = itk::RGBPixel<unsigned char>;
      using ItkImage = itk::Image<Pixel, 2>;
    } // namespace

    void
    write_png(const RgbImage &image, const std::string &filename)
    {
      auto                 itk_image = ItkImage::New();
      ItkImage::RegionType region;
      ItkImage::SizeType   size  = {{image.width, image.height}};
      ItkImage::IndexType  start = {{0, 0}};
      region.SetSize(size);
      region.SetIndex(start);
      itk_image->SetRegions(region);
      itk_image->Allocate();
      // ITK's first index runs along a row, as RgbImage's pixels do.
      Pixel *pixels = itk_image->GetBufferPointer();
      for (std::size_t p = 0; p < std::size_t(image.width) * image.height; ++p)
        for (unsigned int c = 0; c < 3; ++c)
          pixels[p][c] = image.rgb[3 * p + c];
      auto writer = itk::ImageFileWriter<ItkImage>::New();
      writer->SetImageIO(itk::PNGImageIO::New());
      writer->SetFileName(filename);
      writer->SetInput(itk_image);
      try
        {
          writer->Update();
        }
      catch (const itk::ExceptionObject &e)
        {
          throw Error("Cannot write the picture " + filename + ": " +
                      e.GetDescription());
        }
    }

    RgbImage
    read_png(const std::string &filename)
    {
      auto reader = itk::ImageFileReader<ItkImage>::New();
      reader->SetImageIO(itk::PNGImageIO::New());
      reader->SetFileName(filename);
      try
        {
          reader->Update();
        }
      catch (const itk::ExceptionObject &e)
        {
          throw Error("Cannot read the picture " + filename + ": " +
                      e.GetDescription());
        }
      const auto size =
        reader->GetOutput()->GetLargestPossibleRegion().GetSize();
      RgbImage     image(size[0], size[1]);
      const Pixel *pixels = reader->GetOutput()->GetBufferPointer();
      for (std::size_t p = 0; p < std::size_t(image.width) * image.height; ++p)
        for (unsigned int c = 0; c < 3; ++c)
          image.rgb[3 * p + c] = pixels[p][c];
      return image;
    }
  } // namespace Patient
} // namespace softface
