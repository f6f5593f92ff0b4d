//! Frames that must not change: the SHA-256 of every file of a fixed set of renders, recorded
//! before the restructure of issue 25 ("one direction through the renderer"). A change that
//! moves code around must leave every frame, AOV and count bit for bit as it was; a change
//! that means to alter the pixels updates the table below on purpose (the failure prints the
//! whole new table).

use crate::common;

use std::path::Path;

use sha2::{Digest, Sha256};

/// One render through the binary: a name, the spec (relative to the repository) and its flags.
struct Render {
    name: &'static str,
    spec: &'static str,
    flags: Vec<String>,
}

/// The bunny at a quarter of its size: what every method is checked on.
const BUNNY: &str = "anims/bunny-turntable.toml";
const SMALL: &str = "--width 320 --height 240";

fn render(name: &'static str, spec: &'static str, flags: &str) -> Render {
    Render {
        name,
        spec,
        flags: flags.split_whitespace().map(String::from).collect(),
    }
}

fn renders() -> Vec<Render> {
    let mut v = vec![
        // The default animation's first frames at one sample per pixel, as the README's
        // first command rendered them before samples per pixel; then at four samples, as it
        // renders them now (recorded when samples per pixel came).
        render(
            "shapes-turntable",
            "anims/shapes-turntable.toml",
            "--frames 0..3 --spp 1",
        ),
        render(
            "shapes-turntable-spp4",
            "anims/shapes-turntable.toml",
            "--frames 0..2 --spp 4",
        ),
    ];
    for (name, method) in [
        ("bunny-none", "none"),
        ("bunny-brute", "brute"),
        ("bunny-scan-warp-boundary", "scan-warp-boundary"),
        ("bunny-grid-warp-boundary", "grid-warp-boundary"),
        ("bunny-grid-nowarp-boundary", "grid-nowarp-boundary"),
        ("bunny-grid-warp-uncertainty", "grid-warp-uncertainty"),
        ("bunny-grid-nowarp-uncertainty", "grid-nowarp-uncertainty"),
        // Added after the restructure (its first method beyond the paper's).
        ("bunny-scan-nowarp-uncertainty", "scan-nowarp-uncertainty"),
    ] {
        let flags = format!("{SMALL} --frames 0..2 --method {method}");
        v.push(render(name, BUNNY, &flags));
    }
    for (name, flags) in [
        (
            "bunny-nowarp-all",
            "--frames 0..2 --method grid-nowarp-uncertainty --flood-to all",
        ),
        (
            "bunny-nowarp-contrary",
            "--frames 0..2 --method grid-nowarp-uncertainty --flood-to contrary",
        ),
        (
            "bunny-warp-contrary",
            "--frames 0..2 --method grid-warp-uncertainty --flood-to contrary",
        ),
        (
            "bunny-tuned",
            "--frames 1 --h0 8 --min-voters 2 --lights 100 --tile 24",
        ),
        (
            "bunny-scan-block",
            "--frames 1 --method scan-warp-boundary --scan-block 32 --tile 48",
        ),
        ("bunny-validate", "--frames 0..2 --validate"),
        (
            "bunny-validate-warp",
            "--frames 1 --validate --method grid-warp-boundary",
        ),
        (
            "bunny-validate-scan",
            "--frames 1 --validate --method scan-warp-boundary",
        ),
        // Orbit: reprojection. Frames 2..6 start mid-chain, so frames 0 and 1 warm it up.
        (
            "bunny-temporal-orbit",
            "--frames 2..6 --temporal --keyframe 4 --validate",
        ),
        (
            "bunny-temporal-warp",
            "--frames 0..3 --temporal --method grid-warp-uncertainty",
        ),
    ] {
        v.push(render(name, BUNNY, &format!("{SMALL} {flags}")));
    }
    // Spin: votes pulled through the turn, light-space edges.
    v.push(render(
        "bunny-temporal-spin",
        "anims/bunny-spin.toml",
        &format!("{SMALL} --frames 0..4 --temporal --validate"),
    ));
    v
}

/// The recorded hashes: one line per file, `render file sha256`. `stats.csv` is hashed
/// without its `seconds` column, which is a wall-clock time, and without the `spp` column
/// added after most were recorded (checked to be the render's own).
const EXPECTED: &str = "\
shapes-turntable frame_0000.exr c806558a5243cc166e47b86a5c8d2def43d7c0401be92c36b57a7a6dd551c11e
shapes-turntable frame_0000.png 1cbe80db6928cae6252c151ea368e81d6681f0c4d710b4b90db1cfc4bd2a63a3
shapes-turntable frame_0001.exr a51ef6e69ff15578f558df9dc01a4fdf7c86ed84614d381f0034d47a77546083
shapes-turntable frame_0001.png 640aaba349e431b8cf26e7b8dfa99be725775606f25c06aa7cc4c1aa3581343b
shapes-turntable frame_0002.exr ca45b81a0cf78ba3df7f2671afea3496df90a7e39104394c0be06e6238cedc8e
shapes-turntable frame_0002.png 7782ce016d8711a540b0bc783d6b6f9d7122a4e38cd79b66c234b9510a0028dc
shapes-turntable lights.json 2657dd11c380f9acd9d07d3f80e0f577c5784f8140e89778490c04deb0b09c1c
shapes-turntable stats.csv 6c9bf6a07586f6cb955257924cb9255647d18f46190f5d7fed02b99bf10bcb70
shapes-turntable-spp4 frame_0000.exr 7d8e53b4a85d911ca29bb6228d8661482d45b0c2666872fc1fd7b98121876825
shapes-turntable-spp4 frame_0000.png f2260c5b38912a03fb88474b1d51e8eb32b021de6d2136e99e0214a886eace13
shapes-turntable-spp4 frame_0001.exr c1809baae92e0f7af7e4136322f4a2e555f5b0f4c088dbe42d5d29aead1a7ef5
shapes-turntable-spp4 frame_0001.png 9b76d7ca74a34dae4b0dc7c272520cd306f37624b45bfed726758bdbb6ce7293
shapes-turntable-spp4 lights.json 2657dd11c380f9acd9d07d3f80e0f577c5784f8140e89778490c04deb0b09c1c
shapes-turntable-spp4 stats.csv 540850352825ebd026f88ab680b5861a893a3a7aa24461a346619bfeaaca3a45
bunny-none frame_0000.exr 143a3c8552910db6c8f644465d807eeac4556d64ce676cd45f22fa7d197e2c54
bunny-none frame_0000.png 2be32b9b64b88f6561e705ed85b82b2f1e1869ca05935dd8c0abc517a26bca04
bunny-none frame_0001.exr c925aac1fc4ecf77e307d39ac0bb5d79b0ebc79bd2eb5a2cc91509caae8f9a40
bunny-none frame_0001.png f36b569d2b6f31344aea7e04d4617ee2961062a53e3739ef1a08aab88d190f9b
bunny-none lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-none stats.csv 4c4d99b6e2a7725ce47297c5040ca65ca89e183accf6fdb359f64af6831b8304
bunny-brute frame_0000.exr c2e0ebd1680930548affbf1b3672aa4beab871e0799472608db6f77043d8b2e2
bunny-brute frame_0000.png d5d0f4cee8224f15149e5c880595025ed1f0bc1d47726cfa46bc9af8140bafb2
bunny-brute frame_0001.exr 23d85930817be5860b3540ce7d131807f977dbdc87cb56800cf2827652c7e0e1
bunny-brute frame_0001.png dba912b608c09e00306d067b9e49a10d749caf52d3cb184ad28efead32e4eac2
bunny-brute lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-brute stats.csv c91b32b95b194dc3164e7cd570bc988b19a0babcd0a812e1c726d1fcf6e96c4a
bunny-scan-warp-boundary frame_0000.exr a6cd5245294a78a6803b854f05d7f4807cfce6c3b9a094e28848169e2fa9dbbf
bunny-scan-warp-boundary frame_0000.png 5fd3141a558a72ca939f54caf0fefd3c98e93b799f216d9ebe44d1ae4ee1f59e
bunny-scan-warp-boundary frame_0001.exr 806a1448c3485b1e965da33a1a9a8ba828e7b84832706f38f4cacf2c93ea32fe
bunny-scan-warp-boundary frame_0001.png f7215385a0f4bf8399a4e4fb19d5ecfd689b9d28fe61c96a316e0922b6c35f8a
bunny-scan-warp-boundary lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-scan-warp-boundary stats.csv c9a1c6ae5b76b7bd35b8fcfbe8bc70ef0ada34d265400dc2c534a5036e9932dd
bunny-grid-warp-boundary frame_0000.exr ca287a6bf67c0b6c6a12451a973fce604c01381707d7463d00d6abd9361df2b9
bunny-grid-warp-boundary frame_0000.png 6cf7147c6a2b83bd6f6fa8e33bb9f05ac72f147ecb3dae382952e83b367ca556
bunny-grid-warp-boundary frame_0001.exr eec0229b9fe7eb1f41f1a89b5e3385878b90c42aad783cb33df5430833a46956
bunny-grid-warp-boundary frame_0001.png cf039ebcce52fa12fad73670ed689a97fb517644e289ee1a4435e4731b5284c0
bunny-grid-warp-boundary lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-grid-warp-boundary stats.csv 13f591846bdc1be5c5e8013a9905251fc8f63373bc28fa925c06ae7e5d3bd7c8
bunny-grid-nowarp-boundary frame_0000.exr 4c7fa06dabb3a18a0259f28220e345064b7d90e92cf52fece51fce942bbf14df
bunny-grid-nowarp-boundary frame_0000.png dd1f280e669f942027da4f014daac80a2b6bebd24100ce8f59097166999e9622
bunny-grid-nowarp-boundary frame_0001.exr 11dd8e5913b94078aded19e8b2b551909498f4f17be25b23c7b9039ab95bb932
bunny-grid-nowarp-boundary frame_0001.png e96bd4cc0e8c05783b9d28b86bcc2e4677b9afd373e211c8cc9d0fa10a24c2c0
bunny-grid-nowarp-boundary lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-grid-nowarp-boundary stats.csv ba1ae35c496ed9b0ecd7ab70677a0756b3077691f29d9f96899e94801410978f
bunny-grid-warp-uncertainty frame_0000.exr c115098f19557337317273cb0ba46bf7eab5161dacdeef235ea474aa28638e2d
bunny-grid-warp-uncertainty frame_0000.png d62681e42fe41d1aece97838a9e04400ebead4b7fa7063ff852b7f3bff6502da
bunny-grid-warp-uncertainty frame_0001.exr ff85943daffc7541ef69e996f6fece7c99bd39725ef3b1d8fab84ae99e7b1686
bunny-grid-warp-uncertainty frame_0001.png c402321d6138474b3e9c80c7b0e6e23c3a6a799704cf55dec969b7f8ea481c88
bunny-grid-warp-uncertainty lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-grid-warp-uncertainty stats.csv 91e824f4cfc817cba719bc740ae8d5a8e661e35472b36a1b85d34b64337c123c
bunny-grid-nowarp-uncertainty frame_0000.exr 479bc95234099f25822e9b5c05191aa609286ce2a2406ae292f1d8eb505d2d51
bunny-grid-nowarp-uncertainty frame_0000.png 36d89005acb15a2bc3a17a9265d20085409d3a5ede169ba619b8c6948efdcee4
bunny-grid-nowarp-uncertainty frame_0001.exr 1a41059d2f695cc294e5919fe9b040dd9d2c19604058651ee15c2cf0021bd2ed
bunny-grid-nowarp-uncertainty frame_0001.png a588aa398b34dc9d68d376ec889ef0a0435728775bf7a5fab26dbe490fedb166
bunny-grid-nowarp-uncertainty lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-grid-nowarp-uncertainty stats.csv d63ace7478a6b8a9b472255cf438ea528260fbe92b523e4e91da28ae8154364a
bunny-scan-nowarp-uncertainty frame_0000.exr 612c46461b5eaa0d4fcf942b87110741051c332b6aa875cd6b437b964b01c0a8
bunny-scan-nowarp-uncertainty frame_0000.png 28fb254a8e4fbfffe510492e1bf99c5ded26fedf4c50c7feca3aafbce1163b01
bunny-scan-nowarp-uncertainty frame_0001.exr 060061b180496afba8785f89fdb9484ebb46875c7cffc509960dc8b9bbf5e870
bunny-scan-nowarp-uncertainty frame_0001.png 90a9a59b825273a92411c84b55a44f656b599b23263fb656aaed7034ef3b9f7b
bunny-scan-nowarp-uncertainty lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-scan-nowarp-uncertainty stats.csv 50580d78c06d00f6fddc5599b4db4d7de834f084586e8a828ed8ccdca4d5d1c7
bunny-nowarp-all frame_0000.exr 57a0414040fc2eedbdc2bff3a7354daecb5b6169413c58f54ef3541f5701ac06
bunny-nowarp-all frame_0000.png 687db2f08acc671d0aa42089f976a38419f4684190c3e1381fc9dc0449e26c86
bunny-nowarp-all frame_0001.exr ddd850dcc2f3432185a504d26ae5b8fdda1cec4fbf7a9526ad762dad5f25cb63
bunny-nowarp-all frame_0001.png c51be667bbef07dfb1c7eb2b9a6d831fbda842f173020747ed9226fa2616bbcf
bunny-nowarp-all lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-nowarp-all stats.csv 0d079f68c86ee79b15dfde1c0c5ee5ecd60c5dda6c5233d9be53f7eaae6195a6
bunny-nowarp-contrary frame_0000.exr abac535594909a2f90bb3aa17004c4872d8c420b800b8ca8f744ba6b85ac017d
bunny-nowarp-contrary frame_0000.png 7c90091428b3f840c06b5e9486d4502aa95de3e2e87af339116ddc3aa762e573
bunny-nowarp-contrary frame_0001.exr 3bb743335a7880df3e61c8ec597a12a2067b75d32016eac88f4cbcca0026b21a
bunny-nowarp-contrary frame_0001.png 5a69c8ba09df73d1beb8095e2da475d84005cf95571ee75e9eddedbade646743
bunny-nowarp-contrary lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-nowarp-contrary stats.csv 3e387c5047a6f9db667ae5ccf8ba3a826c126d23de7af5c3760b91cc0353fc84
bunny-warp-contrary frame_0000.exr fd467ce7cd6fbb58a29fd0d8f3e3f0a118275d96a5eee839e1b261e92b21a751
bunny-warp-contrary frame_0000.png 12f4af91d7f6c3c728bf2d0307648c9a46da50b9ca4d521c40ed7603145d8f5f
bunny-warp-contrary frame_0001.exr 2689672e72313d9ee466cf0c58e745be38c7e4a5840d1320d53577c90bb45dab
bunny-warp-contrary frame_0001.png 1d61a2f4d001df383ba27670b4dcfa454c971cd44fd344f37bc744ec312dbc28
bunny-warp-contrary lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-warp-contrary stats.csv 70f5ddb9efa35a6c54a7bcd89487af9160f38a56863c7c7218cf5306b6fcb502
bunny-tuned frame_0001.exr 530f7b9095b621b8843d01b2c768626994fb021f31e755357be29b33fc461064
bunny-tuned frame_0001.png e0e94b42ecdbaf0d50351bf10a18c8f1d5ee7fc35f083f6583cca42af12bf8ae
bunny-tuned lights.json 2818e3a7505bbe64692862b89bd3544ab4528eb36fb259286b4cf66d037f4bad
bunny-tuned stats.csv 2722223dd2135845d95cc8878a62403f7f49961127b19f511b00e56a0cb0792f
bunny-scan-block frame_0001.exr dc913666d060ca4fcce7eca5e74efbb42c5089bd6c2c889b914fac50496c3d67
bunny-scan-block frame_0001.png ab692854adb1843df408835cf22226846b327f24455ba8ae045937df69f29c0e
bunny-scan-block lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-scan-block stats.csv e7a4f6dea3142ee1fe65792fa512ef3f1a62fe49ecff9c8d7f9b834ee1684180
bunny-validate frame_0000.exr e98ee85e1cccedfe84beb4b729637c9faf67bb512f01a493c7436a7bb9aef6c4
bunny-validate frame_0000.png 36d89005acb15a2bc3a17a9265d20085409d3a5ede169ba619b8c6948efdcee4
bunny-validate frame_0001.exr 743e1ebf0f4fd7516ef027b1b13a9686f573d7634dca87d679de5979adaa1051
bunny-validate frame_0001.png a588aa398b34dc9d68d376ec889ef0a0435728775bf7a5fab26dbe490fedb166
bunny-validate lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-validate stats.csv 947bdbc729aa73424ae2e963b65ca0006ecc05ed94c71943dbe492bb035a35a7
bunny-validate-warp frame_0001.exr e23f36818419363ddfe4da6b2ecf410a34d42431b7776d733fb8d2241a7cb730
bunny-validate-warp frame_0001.png cf039ebcce52fa12fad73670ed689a97fb517644e289ee1a4435e4731b5284c0
bunny-validate-warp lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-validate-warp stats.csv 0628aad782b05ca140bf43d7994d991fb5606232a1bb61fa05adaf6874e3a755
bunny-validate-scan frame_0001.exr a8404cb2dae6aa5d1511dbff5340acdf4af1e5405026fdb59546a304b26e1a52
bunny-validate-scan frame_0001.png f7215385a0f4bf8399a4e4fb19d5ecfd689b9d28fe61c96a316e0922b6c35f8a
bunny-validate-scan lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-validate-scan stats.csv cdf403cd496709e665595871499fd30526622b47db9f4d8e110d2ae84fbdb0b3
bunny-temporal-orbit frame_0002.exr 0a797366459850624664f609808a6dbbcbd222e4b8d010527b224e79bad9ca18
bunny-temporal-orbit frame_0002.png 11cb17bf36477693f22b9594251b4ef90e3a38166b47368f1a213de6e97b9d2f
bunny-temporal-orbit frame_0003.exr a0a755439e349f69d141114e1096f7f4e6b69740948dc5cfc073af49721e5642
bunny-temporal-orbit frame_0003.png 5fde6bed0e96aa71b493670c985ef47c68b4239cf21b80fd33833b6b0f18c512
bunny-temporal-orbit frame_0004.exr 6ca9a1671a72d3b1449c2a3b33544246f8099e7bcdc4e16e85a622eeaa5af843
bunny-temporal-orbit frame_0004.png 220fea221db296f9497aae37374245a45101f724a00287fc8c968a8d72c8806b
bunny-temporal-orbit frame_0005.exr 117538ea6de5da77fbaa90ea99f33604beed3899489e19ab7ddc761fde9a0b03
bunny-temporal-orbit frame_0005.png 4e9117ab374c63ee2e931e613f2bb758689cf3f84e1e00e68cd547f1f0f1a627
bunny-temporal-orbit lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-temporal-orbit stats.csv 301962c1b35687e22e3fb3868b1d3cf48775ac0b2405a27c75c1eb1398184c4b
bunny-temporal-warp frame_0000.exr c115098f19557337317273cb0ba46bf7eab5161dacdeef235ea474aa28638e2d
bunny-temporal-warp frame_0000.png d62681e42fe41d1aece97838a9e04400ebead4b7fa7063ff852b7f3bff6502da
bunny-temporal-warp frame_0001.exr f9a62435c281f992c67957db17eed8a000ae4f8d01520c999901401edcfa07f7
bunny-temporal-warp frame_0001.png 9fe17d27d1b01a42090bb07bf58230e0ac81edad01e325219769e1cb242b2ced
bunny-temporal-warp frame_0002.exr be18706cb0a32c2e6f8560950577041dcad4b05287027b016ac64ba49608a80c
bunny-temporal-warp frame_0002.png f9275db509c0e55ad439977488bacfc2b17366f85b89da00d4b1ecf8e5e3412d
bunny-temporal-warp lights.json 9b3fc8976c763dca6ede3decd8aae22545e7b4663c1f239ade31cd5721afa7b4
bunny-temporal-warp stats.csv b142fb3c4771ca9afe636e236abddb1547ad48f2feff6a2ac1ff31ec73f0c83b
bunny-temporal-spin frame_0000.exr 37c49c15cbdd937f76c1148bbbaecab53089238aeb7cbbd02582625fc8dc6226
bunny-temporal-spin frame_0000.png cbcde078458657b213958e01b8efca4054b4327fd7dcd6ac55081566b813bd24
bunny-temporal-spin frame_0001.exr ccca5e58572d630f2af144a43d6e43e42ab6b4fa9968a7877d5dc7c7945082a2
bunny-temporal-spin frame_0001.png 63955a523021056dec31e560489f5b48dee7732395f736562dcaaf27576407d3
bunny-temporal-spin frame_0002.exr a6436d9fd1bbfa41cecdb77460223d7ba30432a20001a6bd1daaed662c5f7a77
bunny-temporal-spin frame_0002.png c073db07a82bafe5bf5a84e5a12f03f343d2abad4629c7249af413809d19be82
bunny-temporal-spin frame_0003.exr a4959f93dddec81a036da339bb927f32a5381e798ec54b06819af9ed600ce0ce
bunny-temporal-spin frame_0003.png 78b5a17254ee8c90e2825976354068bd35f8f940172b58333e3de19b9c719f8d
bunny-temporal-spin lights.json ceecc097a75a476c4f668026c5620b218c106d77b91c9d471b3559e773bb1ce5
bunny-temporal-spin stats.csv d1ba2f1d56dc1790cf707fc6535341e6f9e40b40a9b212542caa9f26fa8c5625
";

fn sha(bytes: &[u8]) -> String {
    format!("{:x}", Sha256::digest(bytes))
}

/// `stats.csv` with the `seconds` column emptied and the last column, `spp`, removed once
/// checked to be `spp` everywhere.
fn stats_without_seconds(text: &str, spp: &str) -> String {
    let mut lines = text.lines();
    let mut header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "seconds")
        .expect("stats.csv has a seconds column");
    assert_eq!(
        header.pop(),
        Some("spp"),
        "stats.csv ends with the spp column"
    );
    let mut out = format!("{}\n", header.join(","));
    for line in lines {
        let mut f: Vec<&str> = line.split(',').collect();
        f[col] = "";
        assert_eq!(f.pop(), Some(spp), "a golden render at {spp} spp: {line}");
        out.push_str(&f.join(","));
        out.push('\n');
    }
    out
}

/// The output files of one render folder (frames, lights, stats), hashed, in name order.
/// `lights.json` names the map it came from: the assets folder is hashed as `ASSETS`, so the
/// hashes do not depend on where the repository and its assets are. The bookkeeping for
/// `--resume` (`settings.txt`, `records/`) is not output.
fn hashes(dir: &Path, assets: &str, spp: &str) -> Vec<(String, String)> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "settings.txt" && dir.join(n).is_file())
        .collect();
    names.sort();
    names
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(dir.join(&n)).unwrap();
            let h = if n == "stats.csv" {
                sha(stats_without_seconds(&String::from_utf8(bytes).unwrap(), spp).as_bytes())
            } else if n == "lights.json" {
                sha(String::from_utf8(bytes)
                    .unwrap()
                    .replace(assets, "ASSETS/")
                    .as_bytes())
            } else {
                sha(&bytes)
            };
            (n, h)
        })
        .collect()
}

#[test]
fn every_recorded_frame_keeps_its_bits() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let assets = common::assets_dir();
    let mut got: Vec<(String, String, String)> = Vec::new();
    for r in renders() {
        let out = tmp.path().join(r.name);
        // The specs name their files under ../assets; point them at the test assets.
        let text = std::fs::read_to_string(root.join(r.spec)).unwrap();
        let spec = tmp.path().join(format!("{}.toml", r.name));
        let dir = format!("{}/", assets.display());
        std::fs::write(&spec, text.replace("../assets/", &dir)).unwrap();
        let o = common::bin()
            .args(["render", "-q", "--no-report"])
            .arg(&spec)
            .args(&r.flags)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{}: {}",
            r.name,
            String::from_utf8_lossy(&o.stderr)
        );
        let spp = r
            .flags
            .iter()
            .position(|f| f == "--spp")
            .map_or("1", |k| r.flags[k + 1].as_str());
        for (file, h) in hashes(&out, &dir, spp) {
            got.push((r.name.to_string(), file, h));
        }
    }
    let table: String = got
        .iter()
        .map(|(r, f, h)| format!("{r} {f} {h}\n"))
        .collect();
    let expected: Vec<(String, String, String)> = EXPECTED
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(' ').collect();
            (f[0].to_string(), f[1].to_string(), f[2].to_string())
        })
        .collect();
    let changed: Vec<String> = got
        .iter()
        .filter(|g| !expected.contains(g))
        .map(|(r, f, _)| format!("{r}/{f}"))
        .chain(
            expected
                .iter()
                .filter(|e| !got.iter().any(|g| g.0 == e.0 && g.1 == e.1))
                .map(|(r, f, _)| format!("{r}/{f} (missing)")),
        )
        .collect();
    assert!(
        changed.is_empty(),
        "{} file(s) changed: {}\nthe new table:\n{table}",
        changed.len(),
        changed.join(", ")
    );
}
