#include "smap/sim/ProceduralTexture.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

namespace smap::sim
{
namespace
{
using Rng = std::mt19937;

cv::Vec3b randomColour(Rng& rng, int lo = 30, int hi = 230)
{
    std::uniform_int_distribution<int> d(lo, hi);
    return {static_cast<uchar>(d(rng)), static_cast<uchar>(d(rng)), static_cast<uchar>(d(rng))};
}

/// Value noise: sum of bilinearly upsampled random grids, finest octave weakest.
cv::Mat valueNoise(int size, Rng& rng, int octaves, int baseCells)
{
    cv::Mat acc = cv::Mat::zeros(size, size, CV_32FC1);
    float amp = 1.0f, total = 0.0f;
    int cells = baseCells;
    for (int o = 0; o < octaves; o++)
    {
        cv::Mat grid(cells, cells, CV_32FC1);
        std::uniform_real_distribution<float> d(0.0f, 1.0f);
        for (int v = 0; v < cells; v++)
            for (int u = 0; u < cells; u++)
                grid.at<float>(v, u) = d(rng);
        cv::Mat up;
        cv::resize(grid, up, {size, size}, 0, 0, cv::INTER_CUBIC);
        acc += amp * up;
        total += amp;
        amp *= 0.55f;
        cells = std::min(size, cells * 2);
    }
    return acc / total;
}

cv::Mat tint(const cv::Mat& gray, const cv::Vec3b& dark, const cv::Vec3b& light)
{
    cv::Mat out(gray.size(), CV_8UC3);
    for (int v = 0; v < gray.rows; v++)
    {
        for (int u = 0; u < gray.cols; u++)
        {
            const float t = std::clamp(gray.at<float>(v, u), 0.0f, 1.0f);
            for (int c = 0; c < 3; c++)
                out.at<cv::Vec3b>(v, u)[c] =
                    cv::saturate_cast<uchar>(dark[c] + t * (light[c] - dark[c]));
        }
    }
    return out;
}

void addStrokes(cv::Mat& img, Rng& rng, int count, int maxLen)
{
    std::uniform_int_distribution<int> pos(0, img.cols - 1), len(maxLen / 4, maxLen), th(1, 3);
    for (int i = 0; i < count; i++)
    {
        const cv::Point a(pos(rng), pos(rng));
        const cv::Point b(a.x + len(rng) * ((i % 2) ? 1 : 0), a.y + len(rng) * ((i % 2) ? 0 : 1));
        cv::line(img, a, b, cv::Scalar(randomColour(rng, 0, 120)), th(rng), cv::LINE_AA);
    }
}

cv::Mat noiseTexture(int size, Rng& rng)
{
    cv::Mat img =
        tint(valueNoise(size, rng, 6, 4), randomColour(rng, 40, 120), randomColour(rng, 150, 240));
    addStrokes(img, rng, size / 16, size / 6);
    return img;
}

cv::Mat paintTexture(int size, Rng& rng)
{
    const cv::Vec3b base = randomColour(rng, 150, 225);
    cv::Vec3b darker;
    for (int c = 0; c < 3; c++)
        darker[c] = static_cast<uchar>(base[c] * 0.86);
    cv::Mat img = tint(valueNoise(size, rng, 4, 3), darker, base);
    addStrokes(img, rng, size / 96, size / 10);
    return img;
}

cv::Mat tilesTexture(int size, Rng& rng)
{
    std::uniform_int_distribution<int> small(0, 1000);
    cv::Mat img(size, size, CV_8UC3, cv::Scalar(randomColour(rng, 150, 220)));
    const int n = 4 + small(rng) % 5;
    const int step = size / n;
    for (int i = 0; i < n; i++)
    {
        for (int j = 0; j < n; j++)
        {
            cv::Vec3b c = randomColour(rng, 60, 230);
            cv::rectangle(img, {i * step + 2, j * step + 2},
                          {(i + 1) * step - 3, (j + 1) * step - 3}, cv::Scalar(c), cv::FILLED);
            if ((i + j) % 3 == 0)
                cv::circle(img, {i * step + step / 2, j * step + step / 2}, step / 5,
                           cv::Scalar(randomColour(rng)), 2, cv::LINE_AA);
        }
    }
    cv::Mat noise = valueNoise(size, rng, 4, 16);
    cv::Mat noise8;
    noise.convertTo(noise8, CV_8UC1, 60.0, -30.0);
    cv::Mat n3;
    cv::cvtColor(noise8, n3, cv::COLOR_GRAY2BGR);
    cv::add(img, n3, img);
    return img;
}

cv::Mat woodTexture(int size, Rng& rng)
{
    std::uniform_int_distribution<int> small(0, 1000);
    cv::Mat g(size, size, CV_32FC1);
    const cv::Mat warp = valueNoise(size, rng, 3, 3);
    const float rings = 6.0f + static_cast<float>(small(rng) % 8);
    for (int v = 0; v < size; v++)
    {
        for (int u = 0; u < size; u++)
        {
            const float x = static_cast<float>(u) / size, y = static_cast<float>(v) / size;
            const float r = std::sqrt((x - 0.3f) * (x - 0.3f) * 0.05f + y * y) * rings +
                            2.5f * warp.at<float>(v, u);
            g.at<float>(v, u) = 0.5f + 0.5f * std::sin(r * 6.2832f);
        }
    }
    cv::Mat img = tint(g, {20, 50, 90}, {90, 150, 200});
    addStrokes(img, rng, size / 32, size / 3);
    return img;
}

cv::Mat posterTexture(int size, Rng& rng)
{
    std::uniform_int_distribution<int> small(0, 1000);
    cv::Mat img(size, size, CV_8UC3, cv::Scalar(230, 235, 240));
    std::uniform_int_distribution<int> pos(0, size - 1), rad(size / 20, size / 5);
    for (int i = 0; i < 12; i++)
    {
        const cv::Scalar c(randomColour(rng));
        if (i % 2)
            cv::circle(img, {pos(rng), pos(rng)}, rad(rng), c, cv::FILLED, cv::LINE_AA);
        else
            cv::rectangle(img, cv::Rect(pos(rng), pos(rng), rad(rng) * 2, rad(rng)), c, cv::FILLED);
    }
    for (int line = 0; line < 8; line++)
    {
        const int y = size * 2 / 3 + line * size / 30;
        for (int x = size / 10; x < size * 9 / 10; x += size / 40 + small(rng) % (size / 30 + 1))
            cv::line(img, {x, y}, {x + size / 60 + 1, y}, cv::Scalar(30, 30, 30), 2);
    }
    return img;
}

cv::Mat fabricTexture(int size, Rng& rng)
{
    std::uniform_int_distribution<int> small(0, 1000);
    cv::Mat img(size, size, CV_8UC3, cv::Scalar(randomColour(rng, 40, 200)));
    const cv::Scalar stripe(randomColour(rng, 20, 240));
    const int period = size / (6 + small(rng) % 10);
    for (int x = 0; x < size; x += period)
        cv::rectangle(img, {x, 0}, {x + period / 3, size}, stripe, cv::FILLED);
    if (small(rng) % 2)
        for (int y = 0; y < size; y += period)
            cv::rectangle(img, {0, y}, {size, y + period / 4}, cv::Scalar(randomColour(rng)),
                          cv::FILLED);
    cv::Mat noise = valueNoise(size, rng, 3, 32), n8, n3;
    noise.convertTo(n8, CV_8UC1, 50.0, -25.0);
    cv::cvtColor(n8, n3, cv::COLOR_GRAY2BGR);
    cv::add(img, n3, img);
    return img;
}

cv::Mat carpetTexture(int size, Rng& rng)
{
    cv::Mat img =
        tint(valueNoise(size, rng, 6, 32), randomColour(rng, 30, 90), randomColour(rng, 100, 200));
    std::uniform_int_distribution<int> pos(0, size - 1);
    for (int i = 0; i < size * 2; i++)
        img.at<cv::Vec3b>(pos(rng), pos(rng)) = randomColour(rng, 0, 255);
    addStrokes(img, rng, size / 10, size / 8);
    return img;
}

}  // namespace

cv::Mat makeTexture(TextureKind kind, int size, uint32_t seed)
{
    Rng rng(seed * 2654435761u + static_cast<uint32_t>(kind));
    switch (kind)
    {
        case TextureKind::Noise:
            return noiseTexture(size, rng);
        case TextureKind::Tiles:
            return tilesTexture(size, rng);
        case TextureKind::Wood:
            return woodTexture(size, rng);
        case TextureKind::Poster:
            return posterTexture(size, rng);
        case TextureKind::Fabric:
            return fabricTexture(size, rng);
        case TextureKind::Carpet:
            return carpetTexture(size, rng);
        case TextureKind::Paint:
            return paintTexture(size, rng);
    }
    return {};
}
}  // namespace smap::sim
