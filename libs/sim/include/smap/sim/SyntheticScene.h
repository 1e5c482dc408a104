// A furnished office room with procedural textures, and the people in it.
#pragma once

#include <Eigen/Core>
#include <map>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "smap/sim/CameraMotion.h"
#include "smap/sim/Person.h"
#include "smap/sim/PersonSprite.h"
#include "smap/sim/SceneObject.h"
#include "smap/sim/SpriteBillboard.h"

namespace smap::sim
{
class SyntheticScene
{
public:
    /// A 6 x 5 x 2.8 m office: textured walls, floor and ceiling, a door, a window, a desk
    /// (diningtable) with a monitor, chairs, a sofa, a potted plant and shelves; `walking`
    /// people on paths through the free floor (0 - 3) and `sitting` people (0 - 2: at the desk,
    /// on the side chair), drawn from the standing and the sitting `sprites`. Same seed, same
    /// scene. Throws core::InputError when people are asked for and `sprites` has none of
    /// their posture.
    static SyntheticScene makeOffice(uint32_t seed, int walking, int sitting,
                                     const std::vector<PersonSprite>& sprites);
    /// A ring corridor 2 m wide around a 12 x 6 m block (outer walls 16 x 10 m, 2.6 m
    /// high): walls in panels of different textures (one in three plainly painted) with
    /// posters, doors, cabinets and plants along them, so that every place looks different;
    /// `walking` people (0 - 3) walking up and down the corridor. The camera
    /// path is loopPath(): a lap is 43.0 m, at 1 m/s.
    static SyntheticScene makeCorridorLoop(uint32_t seed, int walking,
                                           const std::vector<PersonSprite>& sprites);
    /// The camera path of the corridor loop (the corridor's centre line, rounded corners).
    static LoopPath loopPath();

    const std::vector<cv::Mat>& textures() const { return textures_; }
    const std::vector<SceneObject>& staticObjects() const { return objects_; }
    const std::vector<Person>& people() const { return people_; }
    /// The billboards people are drawn with (Person::spec().sprite indexes them).
    const std::vector<SpriteBillboard>& personSprites() const { return personSprites_; }
    /// Class id of every instance id present.
    const std::map<uint16_t, uint8_t>& instanceClasses() const { return instanceClasses_; }
    /// Where the camera presets stand and look.
    Eigen::Vector3d cameraBase() const { return {3.0, 0.35, 1.45}; }
    Eigen::Vector3d cameraTarget() const { return {3.0, 3.4, 0.85}; }

private:
    int addTexture(const cv::Mat& t);
    SceneObject& addObject(const std::string& name, uint8_t classId, int texture);
    /// A person drawn with their own billboard of `sprite`, under the next instance id.
    void addPerson(PersonSpec spec, const PersonSprite& sprite);
    void addRoomAndFurniture(uint32_t seed);
    void addCorridorWalls(uint32_t seed);
    void addCorridorFurniture(uint32_t seed);
    void addCorridorPeople(uint32_t seed, int walking, const std::vector<PersonSprite>& sprites);
    /// The standing sprites' indices; throws core::InputError when people are asked for and
    /// there is none.
    static std::vector<size_t> standingSprites(const std::vector<PersonSprite>& sprites,
                                               int walking);
    void addPeople(uint32_t seed, int walking, int sitting,
                   const std::vector<PersonSprite>& sprites);

    std::vector<cv::Mat> textures_;
    std::vector<SceneObject> objects_;
    std::vector<Person> people_;
    std::vector<SpriteBillboard> personSprites_;
    std::map<uint16_t, uint8_t> instanceClasses_;
    uint16_t nextInstance_ = 1;
};
}  // namespace smap::sim
