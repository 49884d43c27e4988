// Decodes LCM messages the way lcm-spy does (lcm.spy.Spy's subscriber): the type looked
// up by fingerprint in lcm.spy.LCMTypeDatabase (which scans the class path), then built
// by its DataInput constructor. Arguments: pairs FILE FIELD; prints "TYPE FIELD=VALUE"
// per message, or "FILE: no type" when the class path lacks its type.
import java.io.DataInput;
import java.lang.reflect.Field;
import java.nio.file.Files;
import java.nio.file.Paths;

import lcm.lcm.LCMDataInputStream;
import lcm.spy.LCMTypeDatabase;

public class SpyDecodeCheck {
  public static void main(String[] args) throws Exception {
    LCMTypeDatabase types = new LCMTypeDatabase();
    for (int i = 0; i + 1 < args.length; i += 2) {
      LCMDataInputStream in = new LCMDataInputStream(Files.readAllBytes(Paths.get(args[i])));
      long fingerprint = in.readLong();
      in.reset();
      Class<?> type = types.getClassByFingerprint(fingerprint);
      if (type == null) {
        System.out.println(args[i] + ": no type");
        continue;
      }
      Object message = type.getConstructor(DataInput.class).newInstance(in);
      Field field = type.getField(args[i + 1]);
      System.out.println(type.getName() + " " + args[i + 1] + "=" + field.get(message));
    }
  }
}
