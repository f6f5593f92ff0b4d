//! Frames that must not change: the SHA-256 of every file of a fixed set of renders, recorded
//! before the restructure of issue 25 ("one direction through the renderer"). A change that
//! moves code around must leave every frame, AOV and count bit for bit as it was; a change
//! that means to alter the pixels updates the table below on purpose (the failure prints the
//! whole new table). Updated once on purpose since: when every transcendental function on the
//! output path moved from the host's C library to the pure-Rust `libm` (issue 20, item 10),
//! which changed last bits (the bunny's frame 0 at 320×240: 306 of 7.77 M queries flipped).
//! Since then these hashes hold on any host whatever its C library. Updated on purpose again
//! for issue 22: the EXR's channels renamed (`shadow.rays`, …) with depth, normal and albedo
//! passes and a header (camera matrices, settings, counts), and the PNGs made through a view
//! transform (AgX by default) and tagged sRGB — every EXR and PNG changed, and the validated
//! renders' stats.csv, whose PSNR is now measured on the AgX previews.
//! The EXR hashes changed once more when every EXR gained its alpha channel `A` (issue 22: all
//! ones over these opaque backgrounds; every other channel, the PNGs and the statistics kept
//! their bits).
//! And once more when the header gained the `[lights] scene_lights` setting (issue 24: the
//! file's own lights; its attribute `envshadow/lights.scene_lights`), the rest unchanged.

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
/// without its `thread_seconds` column, which is a timing, and without the `spp` column
/// added after most were recorded (checked to be the render's own).
const EXPECTED: &str = "\
shapes-turntable frame_0000.exr dee9ff126f6fee8bde8c29ab8268f25e684a96808d67d9bedb8cc6d9f7fdf96c
shapes-turntable frame_0000.png 1f10c919481f258193e9f66c95813f9e414a3554cd1e08934d1a9149a4c555b3
shapes-turntable frame_0001.exr 7a565005305c5584320ffa0c3aeb36b3e420584e1ac25c4ee01e2e336c923a0c
shapes-turntable frame_0001.png 029725d6de9a4d5c30d1574db4af180f6db068763742e58f027d3e086f5266b2
shapes-turntable frame_0002.exr 4883a11e5e1c1b5ebb2af1b9ca51317f5aefcc8b48c6add8bc5ee0a7bb8982f1
shapes-turntable frame_0002.png e962bf93cbfc39be000d61098bbe8e5c4f53131109af13dbea4dc4bac063cb89
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 1a42a982584cfa0f2b48a19bbcc5b168b1cb92d227d6cfc604770d3905e54712
shapes-turntable-spp4 frame_0000.exr 81cc46bbaf2c236a4c9f4db7be39172661c8ec36085e15a75d5d7268c85d414c
shapes-turntable-spp4 frame_0000.png 3001ef5c77757f4ee1e684106fcbfb1774ca443fdc026407d628de97eae7b64e
shapes-turntable-spp4 frame_0001.exr 9b7ec1bdb300daef1d718109bf1f6a2b435a66288d74d7191987e354b4e45ecf
shapes-turntable-spp4 frame_0001.png 9c2c4784bd5b40a9cab6c92841a240dfdf99677ef48ab6d15138157ffe794b85
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 3a33a30f809fcdf2742f15c108a8df5cc41aa4f9d1685aac75ebf292b030921a
bunny-none frame_0000.exr a8b59891cf4004fc055402e33dd56f32a945950a009ba97f9a39a6a10492cf89
bunny-none frame_0000.png d3815e9f495cede07147b61fdbf7575abaa2b1382493c087c0902ab58077d257
bunny-none frame_0001.exr d771cd6b88996a6c2cd7a97c68e4c60b53ca904c525f8b5ae27541980c24467f
bunny-none frame_0001.png e134beec67346727900077c73e7ae89858a8b22d72d4859653eecb71f107011b
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f81d6fe21e7305425deef527fa8b936ee80aa86cbb74e321678e5bc73fda57e5
bunny-brute frame_0000.exr 96aee30c769804a5a98da4eeead570c91c050ba85300aaf61301b841ecfa9591
bunny-brute frame_0000.png ee648a99eb3f1b3129bab45f64dcfa09c3de1cb9711595a4ec51b1462c72f6ca
bunny-brute frame_0001.exr c1f5313172acc99ff8346d48f974ddc2914f36fcd6ff85f8c94628f0b8dda69d
bunny-brute frame_0001.png d81e4b8d6a073bf3881c7a34f7d26cb29a3274c97c196b6d9b5016d7335b8f00
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-scan-warp-boundary frame_0000.exr bf1f4d17edcd2a92d00c7346cba0ae5cd4452707956dc0776c07cd58d3db7081
bunny-scan-warp-boundary frame_0000.png 804c435f3608d295229379f67e43c1a58603dae1dece00a56c870aaf36854c0d
bunny-scan-warp-boundary frame_0001.exr 33eecd8035763a25da837410512f35874bc721c878c8c1477a858c864b80b895
bunny-scan-warp-boundary frame_0001.png 2dc849257a13479c4618640d73bb07656588158050154107107b4b8fdf04975f
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 9a91c445e193e9da2b5567b68a3f396318f29c6f9777ce0c63316b21c9182959
bunny-grid-warp-boundary frame_0000.exr 1c5a741761f8672fe09f710570a96dfd5f27bc9dd10cccae6b2b0cbeaada2343
bunny-grid-warp-boundary frame_0000.png 13634ff9c34bc1459a8dbac161351abb6e894a422cf1302d66c90b5fd5773181
bunny-grid-warp-boundary frame_0001.exr 7167126b04db7fcc437015346e92b9d5c2d54cfc5aad1e1970a4ceeeba08ba85
bunny-grid-warp-boundary frame_0001.png 20b6cd6e42039c9b426e16191be476d86c1f06d93c9a0fe28d49575a71ba3a84
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv aa2bf7c47bf449e1328eede03814407a420a85cb7407600377ea6c32a69c3b91
bunny-grid-nowarp-boundary frame_0000.exr 85250766a63d9908ba88813a5cb47620f93d3fe2b3dd872772afa1aa351153df
bunny-grid-nowarp-boundary frame_0000.png 488355c079614d190780958fa2f1be51c62a9e2112a18f052260cc42b37cabc0
bunny-grid-nowarp-boundary frame_0001.exr b04189e4fd1b121a99a2a1b3d3d34de5bc7bf19c5db379624990caef701f292b
bunny-grid-nowarp-boundary frame_0001.png 8373a13a62ac227a1f61d72f881636bcb9b38320c350c5e8ca61813f19340a6f
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 4e2c57cea6dc9b82fbb3c0f0fb89d68763d418cc91b07c6b59541ad43e1ffa25
bunny-grid-warp-uncertainty frame_0000.exr fefc4e520c0a56d402b4959ed9f1fb97e577a7c0e8119ed8f287f883d3016177
bunny-grid-warp-uncertainty frame_0000.png 329c5b6ed978e75a4fc4e2f33979dcd0c45f20171297d27b11ad0b9d2cf42a76
bunny-grid-warp-uncertainty frame_0001.exr ba9f5c65b6caef565fe86e357b0f19900de4a3bf0d9a2ca3626f7f80bdac153e
bunny-grid-warp-uncertainty frame_0001.png 16ba91c6b67b44930b15b51e02684bb902e62043f8fefab8044537dcbc504c03
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv da6051bd0dfb48e496c0d8d82a01da4dde690dd40f43bb428b9cc1eced689e31
bunny-grid-nowarp-uncertainty frame_0000.exr a6446cf22be960caa0837c60f418d1328089b10261e1548659a1f97007fc2b01
bunny-grid-nowarp-uncertainty frame_0000.png 5d4da42577491b6d1e702785856cb63832269a726389a295d84205def68fb2d3
bunny-grid-nowarp-uncertainty frame_0001.exr 2d97cde7620bb532ff9b60ae54cedee6deea92368467aee108468d32c5c826f4
bunny-grid-nowarp-uncertainty frame_0001.png 6e9d37d4139549dd4c383e54c75bd551c6d87e7b274e63a181c2f479b1b4be00
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv fd8c465b9216f174c843d130d527009f8642ff070b3b9864d49de208a77b9f3c
bunny-scan-nowarp-uncertainty frame_0000.exr f643d11ece6fad148499918486cdd6611e6f9e63776f9622675eecba33fe233b
bunny-scan-nowarp-uncertainty frame_0000.png b485203cc9847f8e71ee5fd6b05bef0f7e555967de25de0f550f8f650d07955f
bunny-scan-nowarp-uncertainty frame_0001.exr 4f08bf8981d56df3d9338ea5e6312624d9abda656f2ee6d8f51afba3bedfc0f5
bunny-scan-nowarp-uncertainty frame_0001.png a53d4846fd82f2693b3847b971a1d14a32e226c41cff212de42aa7de1062c591
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv 20cc516a50e12509ab9fbc198d16f8a7e5ed37e5e2e529a2f4705cace360a6ec
bunny-nowarp-all frame_0000.exr 9d447f1d398d98bf0819bcb82d80c2cbbace714d7d4e6163ab134f47364b8876
bunny-nowarp-all frame_0000.png 6b6758f14d513eba94f491f05dab7afaa5cda713e077e39e022964a01a1539e7
bunny-nowarp-all frame_0001.exr 6b54f3beeaf466026c773ad912cbdb8d2c00d842811d863a528b30539ca2c2ac
bunny-nowarp-all frame_0001.png 85cec2e4763257c6fdb8dd6a02c443826b2bc2d002bc3eabb450f4419b54ad48
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv 6a2cbcb96d5c7adb62a2878e475572745229f2319865b306db4d7373221342ae
bunny-nowarp-contrary frame_0000.exr 561f5c4f4c07a826d24ab6339a898fd756e9af27d162ebb07b83d0d3a097c88a
bunny-nowarp-contrary frame_0000.png ccc8729899c7988bde8beed16d5e3b42a49894b1f143b63534543d5f8672fe77
bunny-nowarp-contrary frame_0001.exr 804a17343a33f2c411af9d0e7da4150165d6e1241d7de25d26d84120ebfb3195
bunny-nowarp-contrary frame_0001.png f7a524eed226376119696df399f454287b3f6bf265f00210d4c662be1d859c3a
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv e4d99b9574d7ff1331da9ebb04e44af4f719af81194c9933d2d7199bbc6af237
bunny-warp-contrary frame_0000.exr fde0185e52258b09e40a76c888d145dc0c8297c9961ac1e75ec4fed6ec10ead4
bunny-warp-contrary frame_0000.png 47e71ba8c457272d515608e4ece3c77c4358a13b4c88f54f6656148491c09964
bunny-warp-contrary frame_0001.exr 00ea1968387d2db83bcd04036406842dbd0132b01f9cc3f45003dc946c6cf06c
bunny-warp-contrary frame_0001.png 05679531932a1aaf7d6b4fbebd2bb8949915d23cda34ca7ec0516ae60568bfc1
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 18492050db107104367d377cf5077dc390752a9db8982d6fcafade61bf5bebd7
bunny-tuned frame_0001.exr 90b76dd19ce0ef9b754f20377bb101f241aea5cd1b0ae78a5f9287bdade58791
bunny-tuned frame_0001.png 9cfd95a4becb110fd7dd64a08454cc4c7054abb8a0d437b8de42b0ee049a7f99
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv e8701d2de96517a69e08d5360f53e2f277b88d50524aa61a061c5d1c7719c9c0
bunny-scan-block frame_0001.exr e1507e26063b19d78b77c21ce4e0da2ca4e589da745d53e5d128851fc834822d
bunny-scan-block frame_0001.png 33cf75bed588f313f9a34b3092902aa720ad4dc64ce48944311fd25899f4700a
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv f98ef6c8eda859fde763d085d27aae55e6456cd89010e8a05ed9c27adc32a64b
bunny-validate frame_0000.exr c625d00ef3357e4e65dccfebacc93408c730a3884aaaf451f2138a2594013f37
bunny-validate frame_0000.png 5d4da42577491b6d1e702785856cb63832269a726389a295d84205def68fb2d3
bunny-validate frame_0001.exr 4858a5c601a8969073449615df1a1a21efcfccbfc096d53bb4d9b1d3ef1560da
bunny-validate frame_0001.png 6e9d37d4139549dd4c383e54c75bd551c6d87e7b274e63a181c2f479b1b4be00
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv bbbd7da11b2b923066351f338e2ac5ce2226167a5463d6fbe4959c9c26f1bf18
bunny-validate-warp frame_0001.exr 199c9c820d55be72f88dd56fa540250a9a1ee59341a01523c2745ef810768d52
bunny-validate-warp frame_0001.png 20b6cd6e42039c9b426e16191be476d86c1f06d93c9a0fe28d49575a71ba3a84
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 0d4ea4c68d56afcb1ff7ad885546768b08921d8d496c5a2256251b419622bc75
bunny-validate-scan frame_0001.exr ecf1e77df5c8686ca68884278a1d607c84c117f57a7ec8f1ff127ff2d29f0ab4
bunny-validate-scan frame_0001.png 2dc849257a13479c4618640d73bb07656588158050154107107b4b8fdf04975f
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv d669397fc789d7a1064788fd5a9b5656b0c6462bb1254f8f22d4428d75e4c9c8
bunny-temporal-orbit frame_0002.exr 03b5a26c31835d181a59135f0b0a0a52ecaaa7f9327712a492b14da7d352a446
bunny-temporal-orbit frame_0002.png 606afc4a14ff9baa5addfafe7def8fbf8301e24344007175deddfa5a47bf73f4
bunny-temporal-orbit frame_0003.exr b26e7d1717c1414f4939aefa5a94cb40fa9859c61f1947f369bf39bf20310c85
bunny-temporal-orbit frame_0003.png 693f3da294295efca67b87fcdddaddea1daa06f0eedfc9bfda8624d1fae2e74e
bunny-temporal-orbit frame_0004.exr 52aa0d0c03118d9a9d262e3cfa4388ffb2ad7d799e321b69ab5ead6569d94a09
bunny-temporal-orbit frame_0004.png 074162dd669b1ca17dde550bf9dd9d3b1971c4847a3fcb0762e922031714c209
bunny-temporal-orbit frame_0005.exr bff031a1958fcddc36ae638f3ac3b1baca2919969f9cd8de725494603b2e1e61
bunny-temporal-orbit frame_0005.png 647da10a08d70d8c3d051feb3c2a58c06f38475d2aa24657d8dfffe64e44ddc3
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv 4562d3f5b54c2fc0bc0d9a146c20ba93ce00d0209ea8aed28e4098d6407e0b88
bunny-temporal-warp frame_0000.exr ce2499a3cd1284079fead701e31253bd75e1b33e89b937ea90e004a619dc3dbb
bunny-temporal-warp frame_0000.png 329c5b6ed978e75a4fc4e2f33979dcd0c45f20171297d27b11ad0b9d2cf42a76
bunny-temporal-warp frame_0001.exr 7ce36eb72ecb9307e5156ee3f1bd350aa92233ef66b1682dfb4557d088cfcc49
bunny-temporal-warp frame_0001.png 709b10b9174a874ca1921a80cb0e091f3813048edd6f8566d3b9e93be2a58ddd
bunny-temporal-warp frame_0002.exr ec1dc069f3b83d5f65636e7d2bc92431c7cfa23038068ce7a2e354bc59a3fbb3
bunny-temporal-warp frame_0002.png 5226369d039d34adc3176b094879508755c2df9d7c97f9699a84a995d6d8038f
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 3e7d7ced40a8121859edbf11470a184f9450cee9c22794424b93ff8aba9f00ae
bunny-temporal-spin frame_0000.exr 63fbd1931daf98405ea513b1e40d03e6e7c23fa98eedeadcdc6e4f1eaf397d3d
bunny-temporal-spin frame_0000.png 9f6bb526ad5546d98849e75df78a8e336faf0a55143291be85b325d4298c06be
bunny-temporal-spin frame_0001.exr d674d4843a29495081fd4d6050321ab2256c812beba8941f9e466f699d35c412
bunny-temporal-spin frame_0001.png 99a4eed03498fbd061d3686f4187316347cfdcbde65bb98dd1150f59b2e4cc0d
bunny-temporal-spin frame_0002.exr 23e651ab438ca345f807cd1596f919623ae2e4ce36222bdc325197a0377235b2
bunny-temporal-spin frame_0002.png 0d1460f666aeda29708ac6c938bead924fcbbc3e3474796ff4f818cec9e6bf03
bunny-temporal-spin frame_0003.exr 068f3515cae2608f39f588b61052aaa4d70743c3ff3c4b8e49956c641c0c670c
bunny-temporal-spin frame_0003.png a199ae01633444a782ac08602998fdd574e31e92d95cad9408eef35955291bf3
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv e24a7f2009d3a3f14421c63edf99e3e28d5396fff94b580c5af3da57e8a1a2a1
";

fn sha(bytes: &[u8]) -> String {
    format!("{:x}", Sha256::digest(bytes))
}

/// `stats.csv` with the `thread_seconds` column emptied and the last column, `spp`, removed once
/// checked to be `spp` everywhere.
fn stats_without_seconds(text: &str, spp: &str) -> String {
    let mut lines = text.lines();
    let mut header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "thread_seconds")
        .expect("stats.csv has a thread_seconds column");
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
